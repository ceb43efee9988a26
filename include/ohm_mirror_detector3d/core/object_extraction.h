// Stage separateObject of the paper: planar objects from the errorSurface points.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ohm_mirror_detector3d/core/beam_neighbourhood.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct ObjectExtractionConfig
{
  double plane_threshold = 0.05;     // d_thres_plane [m]: RANSAC's inlier distance
  int min_object_points = 9;         // n_object
  double connection_distance = 0.1;  // [m] two surface points closer than this are one patch (r)
  // Patches connected in the sweep's own sampling instead of by connection_distance: two
  // surface points are connected when their beams are neighbours on the grid and the points
  // lie within the neighbourhood's limit (BeamNeighbourhood). Planes are then fitted to each
  // connected group of surface points on its own, and groups that cannot make an object
  // (too few points, or a line) are not fitted at all.
  bool follows_sampling = false;
  BeamNeighbourhoodConfig neighbourhood;
  // A patch must be at least this many beams across in both directions of the grid (the
  // median over its points of the shorter of the two runs of patch beams through the point;
  // on a sweep without a grid: its rectangle this many sample spacings across). A line one or
  // two beams wide is no surface: mixed pixels along a depth edge, whose footprint straddles
  // it and returns from both sides, make such lines.
  int min_beams_across = 3;
  // The full angle of a beam's footprint, in column steps of the sweep (SweepSampling::col_step,
  // the step along a scan line). The rectangle is grown by the part of the sampling spacing
  // the footprint does not cover (see buildObject); 0: thin beams, grown by the whole spacing.
  double footprint_steps = 0.0;
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
  // Each object gets its plane (refit to the patch by least squares on the points within 3
  // robust sigma of it, unit normal towards sensor_origin), its minimum-area rectangle in the
  // plane around those points (centre, axes, width, height; see ReflectiveObject for which side
  // is the width), those points as its surface_inliers, type unknown, and an id counting from 0 in
  // the order found. Deterministic: the same sweep gives the same objects. Clears `objects`
  // first.
  // With follows_sampling (and a grid): first splits the errorSurface points into connected
  // groups on the grid, then runs the loop above in each group that has at least
  // min_object_points points and is min_beams_across across, with patches connected on the
  // grid too. Every patch must be min_beams_across across to become an object.
  void extract(const Sweep& sweep, const SweepSampling& sampling, const Eigen::Vector3f& sensor_origin,
               const SweepLabels& labels, std::vector<ReflectiveObject>& objects);
  // The same with the sampling worked out from the sweep (SamplingEstimator).
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
