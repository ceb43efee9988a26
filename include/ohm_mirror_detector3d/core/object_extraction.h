// Stage separateObject of the paper: planar objects from the errorSurface points.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct ObjectExtractionConfig
{
  double plane_threshold;      // d_thres_plane [m]: RANSAC's inlier distance
  int min_object_points;       // n_object
  double connection_distance;  // [m] two surface points closer than this are one patch (r)
};

// Fits planes to errorSurface points and cuts them into rectangular objects. Owns its
// buffers and reuses them from sweep to sweep.
class ObjectExtractor
{
public:
  explicit ObjectExtractor(const ObjectExtractionConfig& config);

  // While at least min_object_points errorSurface points (both echoes) are not yet assigned to
  // a plane: fits a plane to them by RANSAC (inlier distance plane_threshold), stops when the
  // best plane has fewer inliers than that; splits the plane's inliers into connected patches
  // (two points are connected when closer than connection_distance); every patch of at least
  // min_object_points points becomes an object; all the plane's inliers count as assigned.
  // Each object gets its plane (refit to the patch, unit normal towards sensor_origin), its
  // minimum-area rectangle in the plane (centre, axes, width, height; see ReflectiveObject for
  // which side is the width), its surface_inliers, type unknown, and an id counting from 0 in
  // the order found. Deterministic: the same sweep gives the same objects. Clears `objects`
  // first.
  void extract(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, const SweepLabels& labels,
               std::vector<ReflectiveObject>& objects);

private:
  ObjectExtractionConfig config_;
  // Buffers reused from call to call (PCL types included), defined in
  // object_extraction.cpp so that includers of this header do not compile PCL. Made on
  // the first call; the extractor is movable, not copyable.
  struct Workspace;
  struct WorkspaceDeleter
  {
    void operator()(Workspace* workspace) const;
  };
  std::unique_ptr<Workspace, WorkspaceDeleter> workspace_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
