#!/bin/bash
# `make test-sanitize`: builds the core gtests, the ROS input-conversion gtests and the fuzz
# corpus replay with -fsanitize=address,undefined into their own folder (OUT, outside the
# catkin build, so the normal build is untouched) and runs them; any sanitizer report fails.
# Usage: test/run_sanitized_tests.sh REPO WS OUT   (needs the catkin build in WS for the
# generated message headers).
set -eo pipefail
repo=$1 ws=$2 out=$3
mkdir -p "$out/obj"
CXX=${CXX:-g++}
# Eigen turns off "glibc malloc is already aligned" when it sees __SANITIZE_ADDRESS__ and then frees
# with its own aligned_free, which reads a header that PCL's (uninstrumented) Eigen never wrote:
# a false heap-buffer-overflow on every Eigen::VectorXf that PCL allocated. Same setting as PCL.
CXXFLAGS="-DEIGEN_MALLOC_ALREADY_ALIGNED=1 -std=c++17 -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize=vptr \
  -fno-sanitize-recover=undefined -Wno-deprecated-declarations -Wno-array-bounds \
  -I$repo/include -I$repo/test/fuzz -I$ws/devel/include -I/usr/include/pcl-1.13 -I/usr/include/eigen3 \
  -DOHM_FUZZ_DIR=\"$repo/test/fuzz\""
newest_header=$(find "$repo/include" "$repo/test" -name '*.h' -printf '%T@\n' | sort -n | tail -1)
# Objects of other flags are stale.
if [ "$(cat "$out/flags" 2>/dev/null)" != "$CXX $CXXFLAGS" ]; then rm -f "$out"/obj/*.o; fi
echo "$CXX $CXXFLAGS" > "$out/flags"
export CXX CXXFLAGS out newest_header
compile() {
  src=$1
  obj="$out/obj/$(basename "$(dirname "$src")")_$(basename "$src" .cpp).o"
  if [ -f "$obj" ] && [ "$obj" -nt "$src" ] && [ "$(stat -c %Y "$obj")" -ge "${newest_header%.*}" ]; then
    return 0
  fi
  echo "  CXX $src"
  # shellcheck disable=SC2086
  $CXX $CXXFLAGS -c "$src" -o "$obj"
}
export -f compile
core_sources=$(ls "$repo"/src/core/*.cpp)
ros_sources=$(for f in point_fields conversions dual_return message_walker problem_throttle hokuyo3d_legacy message_pipeline \
  multi_echo_scan parameters; do echo "$repo/src/ros/$f.cpp"; done)
test_sources=$(ls "$repo"/test/core/*.cpp "$repo"/test/ros/test_*.cpp "$repo"/test/fuzz/test_fuzz_corpus.cpp \
  "$repo"/test/fuzz/fuzz_entry.cpp)
echo "$core_sources $ros_sources $test_sources" | tr ' ' '\n' | grep . | xargs -P 2 -I{} bash -c 'compile {}'
obj=$out/obj
LIBS="-lgtest -lpcl_registration -lpcl_sample_consensus -lpcl_search -lpcl_kdtree -lpcl_features -lpcl_common \
  -ltf2_ros -ltf2 -lroscpp -lrosconsole -lroscpp_serialization -lrostime -lcpp_common -lboost_system -lpthread"
core_objects=$(for f in $core_sources; do echo "$obj/core_$(basename "$f" .cpp).o"; done)
ros_objects=$(for f in $ros_sources; do echo "$obj/ros_$(basename "$f" .cpp).o"; done)
core_tests=$(for f in "$repo"/test/core/test_*.cpp; do echo "$obj/core_$(basename "$f" .cpp).o"; done)
ros_tests=$(for f in "$repo"/test/ros/test_*.cpp; do echo "$obj/ros_$(basename "$f" .cpp).o"; done)
# shellcheck disable=SC2086
$CXX $CXXFLAGS $core_tests $core_objects $LIBS -o "$out/test_core"
# shellcheck disable=SC2086
$CXX $CXXFLAGS "$obj/core_test_main.o" $ros_tests $ros_objects $core_objects $LIBS -o "$out/test_input_conversions"
# shellcheck disable=SC2086
$CXX $CXXFLAGS "$obj/core_test_main.o" "$obj/fuzz_test_fuzz_corpus.o" "$obj/fuzz_fuzz_entry.o" $ros_objects \
  $core_objects $LIBS -o "$out/test_fuzz_corpus"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
for test in test_core test_input_conversions test_fuzz_corpus; do
  echo "== $test (address, undefined)"
  "$out/$test" --gtest_brief=1 || status=1
done
exit $status
