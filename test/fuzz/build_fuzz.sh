#!/bin/bash
# Builds the libFuzzer target outside catkin: `test/fuzz/build_fuzz.sh REPO WS OUT`.
# Needs the catkin build in WS first (generated message and config headers). Objects are
# rebuilt only when their source or a header of the package is newer, two at a time.
set -eo pipefail
repo=$1 ws=$2 out=$3
CXX=${CXX:-clang++}
# shellcheck source=../sanitized_objects.sh
source "$repo/test/sanitized_objects.sh"
CXXFLAGS="$SANITIZED_BASE_FLAGS -fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined \
  -Wno-deprecated-declarations $SANITIZED_INCLUDES"
COMPILE_ONLY_FLAGS=-fsanitize=fuzzer-no-link
{ ls "$repo"/src/core/*.cpp; echo "$SANITIZED_ROS_SOURCES"; echo "$repo/test/fuzz/fuzz_entry.cpp"; } \
  | compile_in_parallel "$repo/include" "$repo/test/fuzz"
objects=$(ls "$out"/obj/*.o)
# shellcheck disable=SC2086
$CXX $CXXFLAGS -fsanitize=fuzzer "$repo/test/fuzz/fuzz_prefilter.cpp" $objects $SANITIZED_LIBS -o "$out/fuzz_prefilter"
echo "built $out/fuzz_prefilter"
