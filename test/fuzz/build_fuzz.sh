#!/bin/bash
# Builds the libFuzzer target outside catkin: `test/fuzz/build_fuzz.sh REPO WS OUT`.
# Needs the catkin build in WS first (generated message and config headers). Objects are
# rebuilt only when their source or a header of the package is newer, two at a time.
set -eo pipefail
repo=$1 ws=$2 out=$3
mkdir -p "$out/obj"
CXX=${CXX:-clang++}
SANITIZE="-fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined"
# Eigen turns off "glibc malloc is already aligned" when it sees __SANITIZE_ADDRESS__ and then frees
# with its own aligned_free, which reads a header that PCL's (uninstrumented) Eigen never wrote:
# a false heap-buffer-overflow on every Eigen::VectorXf that PCL allocated. Same setting as PCL.
CXXFLAGS="-DEIGEN_MALLOC_ALREADY_ALIGNED=1 -std=c++17 -O1 -g -fno-omit-frame-pointer $SANITIZE -Wno-deprecated-declarations \
  -I$repo/include -I$repo/test/fuzz -I$ws/devel/include -I/usr/include/pcl-1.13 -I/usr/include/eigen3"
sources=$(ls "$repo"/src/core/*.cpp; for f in point_fields conversions dual_return message_walker hokuyo3d_legacy \
  message_pipeline multi_echo_scan parameters; do echo "$repo/src/ros/$f.cpp"; done; echo "$repo/test/fuzz/fuzz_entry.cpp")
newest_header=$(find "$repo/include" "$repo/test/fuzz" -name '*.h' -printf '%T@\n' | sort -n | tail -1)
# Objects of other flags are stale.
if [ "$(cat "$out/flags" 2>/dev/null)" != "$CXX $CXXFLAGS" ]; then rm -f "$out"/obj/*.o; fi
echo "$CXX $CXXFLAGS" > "$out/flags"
export CXX CXXFLAGS out newest_header
compile() {
  src=$1
  obj="$out/obj/$(basename "$(dirname "$src")")_$(basename "$src" .cpp).o"
  if [ -f "$obj" ] && [ "$obj" -nt "$src" ] && \
     [ "$(stat -c %Y "$obj")" -ge "${newest_header%.*}" ]; then return 0; fi
  echo "  CXX $src"
  # shellcheck disable=SC2086
  $CXX $CXXFLAGS -fsanitize=fuzzer-no-link -c "$src" -o "$obj"
}
export -f compile
echo "$sources" | xargs -P 2 -I{} bash -c 'compile {}'
objects=$(ls "$out"/obj/*.o)
LIBS="-lpcl_registration -lpcl_sample_consensus -lpcl_search -lpcl_kdtree -lpcl_features -lpcl_common \
  -ltf2_ros -ltf2 -lroscpp -lrosconsole -lroscpp_serialization -lrostime -lcpp_common -lboost_system -lpthread"
# shellcheck disable=SC2086
$CXX $CXXFLAGS -fsanitize=fuzzer "$repo/test/fuzz/fuzz_prefilter.cpp" $objects $LIBS -o "$out/fuzz_prefilter"
echo "built $out/fuzz_prefilter"
