// The same stages built the obvious way with PCL's generic tools, for `make bench` to compare
// against (issue 6): a kd-tree radius outlier filter on the whole cloud, RANSAC plane
// segmentation on all candidates, and ICP of each plane's mirrored points against the whole
// scene in front of it. Not part of the package; times only, its output is not used.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/sweep.h"

struct BaselineTimes
{
  double outlier_filter = 0.0;  // pcl::RadiusOutlierRemoval on every in-range point of both echoes
  double echo_comparison = 0.0;
  double planes = 0.0;          // pcl::SACSegmentation (RANSAC) on all candidates, plane after plane
  double icp = 0.0;             // pcl::IterativeClosestPoint per plane against the whole scene in front
  double total = 0.0;
  std::size_t planes_found = 0;
};

BaselineTimes runPclBaseline(const ohm_mirror_detector3d::core::Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                             const ohm_mirror_detector3d::core::Params& params);
