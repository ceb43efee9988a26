# Sourced by test/fuzz/build_fuzz.sh (`make fuzz`) and test/run_sanitized_tests.sh
# (`make test-sanitize`): what both builds outside catkin share. Expects repo, ws, out, CXX set.
#
# Eigen turns off "glibc malloc is already aligned" when it sees __SANITIZE_ADDRESS__ and then frees
# with its own aligned_free, which reads a header that PCL's (uninstrumented) Eigen never wrote:
# a false heap-buffer-overflow on every Eigen::VectorXf that PCL allocated. Same setting as PCL.
SANITIZED_BASE_FLAGS="-DEIGEN_MALLOC_ALREADY_ALIGNED=1 -std=c++17 -O1 -g -fno-omit-frame-pointer"
SANITIZED_INCLUDES="-I$repo/include -I$repo/test/fuzz -I$ws/devel/include -I/usr/include/pcl-1.13 -I/usr/include/eigen3"
# The ROS-side sources the input adapters need (no nodelet, no roscpp node).
SANITIZED_ROS_SOURCES=$(for f in point_fields conversions dual_return md5 message_walker problem_throttle hokuyo3d_legacy \
  legacy_output legacy_outputs message_pipeline multi_echo_scan parameters input_modes sensor_pose_queue sweep_input; do
  echo "$repo/src/ros/$f.cpp"; done)
# dynamic_reconfigure's mutex library: fromConfig (parameters.cpp) reads PreFilterConfig's descriptions.
SANITIZED_LIBS="-lpcl_registration -lpcl_sample_consensus -lpcl_search -lpcl_kdtree -lpcl_features -lpcl_common \
  -ltf2_ros -ltf2 -ltopic_tools -lmessage_filters -lroscpp -lrosconsole -lroscpp_serialization -lrostime -lcpp_common \
  -lboost_system -lpthread -ldynamic_reconfigure_config_init_mutex -lyaml-cpp"

# compile_in_parallel HEADER_DIRS... < SOURCES: compiles each source (one per line) into
# $out/obj/<folder>_<name>.o with $CXX $CXXFLAGS $COMPILE_ONLY_FLAGS, two at a time. An object is
# rebuilt only when its source or a header under HEADER_DIRS is newer; objects of other flags are
# all stale.
compile_in_parallel() {
  mkdir -p "$out/obj"
  newest_header=$(find "$@" -name '*.h' -printf '%T@\n' | sort -n | tail -1)
  if [ "$(cat "$out/flags" 2>/dev/null)" != "$CXX $CXXFLAGS" ]; then rm -f "$out"/obj/*.o; fi
  echo "$CXX $CXXFLAGS" > "$out/flags"
  export CXX CXXFLAGS COMPILE_ONLY_FLAGS out newest_header
  grep . | xargs -P 2 -I{} bash -c '
    src=$1
    obj="$out/obj/$(basename "$(dirname "$src")")_$(basename "$src" .cpp).o"
    if [ -f "$obj" ] && [ "$obj" -nt "$src" ] && [ "$(stat -c %Y "$obj")" -ge "${newest_header%.*}" ]; then
      exit 0
    fi
    echo "  CXX $src"
    # shellcheck disable=SC2086
    $CXX $CXXFLAGS $COMPILE_ONLY_FLAGS -c "$src" -o "$obj"' bash {}
}
