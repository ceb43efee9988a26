// Where the sweep's rays cross one object's plane, on a grid over the plane: the ground both
// growth stages (mirror_growth.h, glass_growth.h) grow an object's extent over. A mirror or a
// pane gives surface echoes only near perpendicular incidence; elsewhere on it the sensor sees
// through it (glass) or via it (mirror) with no echo on the surface. So the plane's real extent
// shows in the rays, not in the surface echoes: a cell through which rays pass to points behind
// the plane is crossed; a cell where rays stop on the plane (a frame, the wall the mirror hangs
// on, a mullion) or before it is a boundary; a cell no ray reached is empty.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/min_area_rectangle.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct ObjectGrowthConfig
{
  bool panes = false;           // grow_objects >= 1
  bool mirrors = false;         // grow_objects == 1
  float plane_threshold = 0.05f;  // d_thres_plane [m]: a return this near the plane lies on it
  float max_growth = 1.5f;      // growth_max_extent [m]: how far beyond its patch an extent may grow on each side
};

// The extent a growth reached: the minimum-area rectangle around the patch and the cells taken,
// in the plane's coordinates along the object's width_axis and height_axis, relative to its
// centre [m] (its sides need not follow the patch's axes: a patch's rectangle is fitted to a
// small, roundish spot and may lie at any angle).
struct GrownExtent
{
  bool grew = false;         // some cell beyond the patch was taken
  bool reached_cap = false;  // the growth reached max_growth on some side (no boundary found there)
  Rectangle2D rectangle;
};

class PlaneCrossings
{
public:
  // Bins every return of the sweep (not nanPoint) that lies on the object's plane or behind it
  // (as seen from `origin`) by where its ray crosses the plane, on a grid covering the object's
  // rectangle grown by max_growth on every side. The cell is about the spacing of the rays on
  // the plane at the rectangle's centre (`angular_step` [rad] times the range, over the cosine
  // of the incidence). A beam with an echo behind the plane crosses it (its echo on the plane,
  // if any, is the object's own surface echo); a beam whose returns lie only on the plane or in
  // front of it, none of them a discontinuous beam's echo (errorSurface or error), marks a
  // boundary where its ray would have met the plane. Nothing is binned when the origin is not in
  // front of the plane.
  void build(const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& origin, float angular_step,
             const ReflectiveObject& object, const ObjectGrowthConfig& config);

  // Grows from the cells inside the object's rectangle (its patch) over neighbouring crossed
  // cells that `accepts(points)` (the points behind the plane that cross the cell, a
  // std::vector<PointRef>), 4-connected, stopping at boundary cells (beams stopped on the plane
  // or before it at least 1 / kBoundaryShare of the crossings: a mullion or a post narrower than a
  // cell shares it with rays passing beside it), at cells it does not accept, and at two empty cells in a row (one empty cell,
  // a gap in the sampling, is bridged). Returns the rectangle around the patch and the centres
  // of the accepted cells.
  template <typename Accepts>
  GrownExtent grow(Accepts accepts);

  static constexpr std::uint32_t kBoundaryShare = 3;

private:
  enum Visit : std::uint8_t
  {
    unvisited = 0,
    grown,    // in the region
    bridged,  // an empty cell passed over (not in the extent)
    stopped,  // looked at and not taken
  };

  std::size_t cellOf(float u, float v) const;
  void reset(std::size_t cells);
  // The cells of the object's rectangle, to start from.
  void seed();
  void include(std::size_t cell);
  // The rectangle around the patch and the included cells.
  void enclose(GrownExtent& extent);

  std::size_t columns_ = 0, rows_ = 0;  // along width_axis, along height_axis
  float cell_ = 0.0f;
  float u0_ = 0.0f, v0_ = 0.0f;  // lower corner of the grid relative to the object's centre
  float half_width_ = 0.0f, half_height_ = 0.0f;
  std::vector<std::uint16_t> boundary_;   // per cell: beams stopped on the plane or before it
  std::vector<std::uint32_t> begin_;      // per cell + 1: the cell's points behind in behind_
  std::vector<PointRef> behind_;          // the points behind the plane, by cell
  std::vector<std::uint8_t> visit_;
  std::vector<std::uint32_t> queue_;
  std::vector<std::pair<std::uint32_t, PointRef>> binned_;  // (cell, point) before sorting
  std::vector<PointRef> cell_points_;     // the points handed to accepts
  std::vector<Eigen::Vector2d> taken_, hull_;  // centres of the cells taken, their hull
};

template <typename Accepts>
GrownExtent PlaneCrossings::grow(Accepts accepts)
{
  GrownExtent extent;
  seed();
  const std::size_t cells = columns_ * rows_;
  for (std::size_t head = 0; head < queue_.size(); ++head)
  {
    const std::size_t cell = queue_[head];
    const bool from_gap = visit_[cell] == bridged;
    const std::size_t column = cell % columns_, row = cell / columns_;
    if (visit_[cell] == grown && (column == 0 || row == 0 || column + 1 == columns_ || row + 1 == rows_))
      extent.reached_cap = true;
    const std::size_t neighbours[4] = { column > 0 ? cell - 1 : cells, column + 1 < columns_ ? cell + 1 : cells,
                                        row > 0 ? cell - columns_ : cells, row + 1 < rows_ ? cell + columns_ : cells };
    for (const std::size_t next : neighbours)
    {
      if (next == cells || visit_[next] == grown || visit_[next] == stopped)
        continue;
      const std::uint32_t crossings = begin_[next + 1] - begin_[next];
      if (crossings == 0 && boundary_[next] == 0)
      {
        // An empty cell: bridged once, from a cell in the region.
        if (!from_gap && visit_[next] == unvisited)
        {
          visit_[next] = bridged;
          queue_.push_back(static_cast<std::uint32_t>(next));
        }
        continue;
      }
      if (visit_[next] == bridged)
        continue;
      cell_points_.assign(behind_.begin() + begin_[next], behind_.begin() + begin_[next + 1]);
      if (kBoundaryShare * boundary_[next] >= crossings || !accepts(cell_points_))
      {
        visit_[next] = stopped;
        continue;
      }
      visit_[next] = grown;
      include(next);
      queue_.push_back(static_cast<std::uint32_t>(next));
    }
  }
  enclose(extent);
  return extent;
}

// Sets the object's rectangle to the grown extent (when it grew), keeping its patch, and
// growth_capped; the more horizontal side stays width_axis.
void applyGrownExtent(const GrownExtent& extent, ReflectiveObject& object);

}  // namespace core
}  // namespace ohm_mirror_detector3d
