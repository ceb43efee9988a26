// Stage separateObject of the paper: planar objects from the errorSurface points.
#pragma once

#include <memory>
#include <vector>

#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Fits planes to errorSurface points and cuts them into rectangular objects. Owns its
// buffers and reuses them from sweep to sweep.
class ObjectExtractor
{
public:
  // While at least params.min_object_points errorSurface points (both echoes) are not yet
  // assigned to a plane: fits a plane to them by RANSAC (inlier distance
  // params.plane_threshold), stops when the best plane has fewer inliers than that; splits
  // the plane's inliers into connected patches (two points are connected when closer than
  // params.outlier_radius); every patch of at least params.min_object_points points becomes
  // an object; all the plane's inliers count as assigned. Each object gets its plane (refit
  // to the patch, unit normal towards sweep.origin), its minimum-area rectangle in the plane
  // (centre, axes, width, height; see ReflectiveObject for which side is the width), its
  // surface_inliers, type unknown, and an id counting from 0 in the order found.
  // Deterministic: the same sweep gives the same objects. Clears `objects` first.
  void extract(const Sweep& sweep, const Params& params, const SweepLabels& labels,
               std::vector<ReflectiveObject>& objects);

private:
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
