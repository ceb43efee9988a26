# The headers most of src/core's sources include, precompiled once per target by the catkin build
# (../../CMakeLists.txt) and the pip build (../../pip/CMakeLists.txt): one list for both.
set(OHM_CORE_PRECOMPILED <Eigen/Core> <Eigen/Geometry> <Eigen/Eigenvalues> <vector> <cmath> <algorithm> <limits>
  <array> <string> <functional>)
