#!/bin/bash
# `make test-sanitize`: builds the core gtests, the ROS input-conversion gtests and the fuzz
# corpus replay with -fsanitize=address,undefined into their own folder (OUT, outside the
# catkin build, so the normal build is untouched) and runs them; any sanitizer report fails.
# Usage: test/run_sanitized_tests.sh REPO WS OUT   (needs the catkin build in WS for the
# generated message headers).
set -eo pipefail
repo=$1 ws=$2 out=$3
CXX=${CXX:-g++}
# shellcheck source=sanitized_objects.sh
source "$repo/test/sanitized_objects.sh"
CXXFLAGS="$SANITIZED_BASE_FLAGS -fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined \
  -Wno-deprecated-declarations -Wno-array-bounds $SANITIZED_INCLUDES -DOHM_FUZZ_DIR=\"$repo/test/fuzz\""
core_sources=$(ls "$repo"/src/core/*.cpp)
# test/ros/test_processing_stats.cpp also tests the diagnostics counters.
ros_sources="$SANITIZED_ROS_SOURCES $repo/src/ros/processing_stats.cpp"
test_sources=$(ls "$repo"/test/core/*.cpp "$repo"/test/ros/test_*.cpp "$repo"/test/fuzz/test_fuzz_corpus.cpp \
  "$repo"/test/fuzz/fuzz_entry.cpp)
echo "$core_sources $ros_sources $test_sources" | tr ' ' '\n' | compile_in_parallel "$repo/include" "$repo/test"
obj=$out/obj
LIBS="-lgtest $SANITIZED_LIBS"
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
