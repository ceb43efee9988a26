#include "ohm_mirror_detector3d/core/plane_crossings.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// A cell of about 1.6 ray spacings: most cells of a plane the sensor sees through hold a
// crossing, and a cell without one (a gap in the sampling) is bridged by the growth.
constexpr float kCellPerSpacing = 1.6f;
constexpr float kMinCell = 0.005f;  // [m]
// Keeps the grid's size bounded for a large cap at a short range (the cell then grows).
constexpr float kMaxCellsPerSide = 1024.0f;
// Incidence steeper than this (the cosine) is taken as this for the cell size: the spacing of
// the rays grows with the incidence, the cell stays a usable size.
constexpr float kMinCosine = 0.5f;

// In plane thresholds: how far in front of the plane a return still marks a boundary.
constexpr float kStopBand = 4.0f;
// Sides whose slopes differ less than this are equally horizontal (a horizontal plane): the
// longer is then the width.
constexpr float kSameTilt = 1e-3f;

bool isDiscontinuousEcho(Label label)
{
  return label == Label::errorSurface || label == Label::error;
}
}  // namespace

void PlaneCrossings::reset(std::size_t cells)
{
  boundary_.assign(cells, 0);
  begin_.assign(cells + 1, 0);
  visit_.assign(cells, unvisited);
  behind_.clear();
  binned_.clear();
  queue_.clear();
}

std::size_t PlaneCrossings::cellOf(float u, float v) const
{
  const float column = std::floor((u - u0_) / cell_);
  const float row = std::floor((v - v0_) / cell_);
  if (!(column >= 0.0f && row >= 0.0f && column < static_cast<float>(columns_) && row < static_cast<float>(rows_)))
    return columns_ * rows_;
  return static_cast<std::size_t>(row) * columns_ + static_cast<std::size_t>(column);
}

void PlaneCrossings::build(const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& origin,
                           float angular_step, const ReflectiveObject& object, const ObjectGrowthConfig& config)
{
  columns_ = rows_ = 0;
  half_width_ = 0.5f * object.width;
  half_height_ = 0.5f * object.height;
  const Eigen::Vector3f normal = object.plane.head<3>();
  const float offset = object.plane[3];
  const float origin_side = normal.dot(origin) + offset;
  const float range = (object.centre - origin).norm();
  if (!(origin_side > config.plane_threshold) || !(angular_step > 0.0f) || !(range > 0.0f) ||
      !(config.max_growth >= 0.0f))
  {
    reset(0);
    return;
  }
  const float width_extent = object.width + 2.0f * config.max_growth;
  const float height_extent = object.height + 2.0f * config.max_growth;
  const float cosine = std::max(kMinCosine, std::min(1.0f, origin_side / range));
  cell_ = std::max({ kMinCell, kCellPerSpacing * angular_step * range / cosine,
                     std::max(width_extent, height_extent) / kMaxCellsPerSide });
  columns_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(width_extent / cell_)));
  rows_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(height_extent / cell_)));
  u0_ = -0.5f * static_cast<float>(columns_) * cell_;
  v0_ = -0.5f * static_cast<float>(rows_) * cell_;
  const std::size_t cells = columns_ * rows_;
  reset(cells);

  const float threshold = config.plane_threshold;
  // Returns nearer the plane than this in front of it stop rays there (a wall in front of a plane
  // fitted a little tilted); a ray stopped further in front leaves its cell empty, and two empty
  // cells in a row end the growth just the same.
  const float stop_band = std::min(kStopBand * threshold, origin_side);
  const Eigen::Vector3f& centre = object.centre;
  const Eigen::Vector3f& width_axis = object.width_axis;
  const Eigen::Vector3f& height_axis = object.height_axis;
  const std::size_t beams = sweep.beamCount();
  for (std::size_t b = 0; b < beams; ++b)
  {
    bool crosses = false;
    std::size_t on_plane_cell = cells;
    for (std::uint8_t k = 0; k < 2; ++k)
    {
      const Label label = labels.echoes[k][b];
      if (label == Label::nanPoint)
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[b];
      // A single return repeated in both echoes counts once.
      if (k == 1 && labels.echoes[0][b] != Label::nanPoint && p == sweep.echoes[0].points[b])
        continue;
      const float side = normal.dot(p) + offset;
      if (!(side < stop_band))
        continue;  // far in front of the plane (or not finite)
      if (side >= -threshold)
      {
        // Stopped on the plane or before it (a frame, the wall, an occluder; a plane fitted a
        // little tilted leaves its wall in front of it): no ray passes there. Unless it is a
        // discontinuous beam's echo: the object's own surface echo.
        if (!isDiscontinuousEcho(label))
        {
          const Eigen::Vector3f stop =
              side > threshold ? Eigen::Vector3f(origin + (origin_side / (origin_side - side)) * (p - origin)) : p;
          const Eigen::Vector3f offset_in_plane = stop - centre;
          on_plane_cell = cellOf(offset_in_plane.dot(width_axis), offset_in_plane.dot(height_axis));
        }
        continue;
      }
      const Eigen::Vector3f crossing = origin + (origin_side / (origin_side - side)) * (p - origin);
      const Eigen::Vector3f offset_in_plane = crossing - centre;
      const std::size_t cell = cellOf(offset_in_plane.dot(width_axis), offset_in_plane.dot(height_axis));
      if (cell == cells)
        continue;
      crosses = true;
      binned_.emplace_back(static_cast<std::uint32_t>(cell), PointRef{ static_cast<std::uint32_t>(b), k });
    }
    if (!crosses && on_plane_cell < cells && boundary_[on_plane_cell] < std::numeric_limits<std::uint16_t>::max())
      ++boundary_[on_plane_cell];
  }
  // Counting sort of the points behind by cell.
  for (const auto& entry : binned_)
    ++begin_[entry.first + 1];
  for (std::size_t c = 0; c < cells; ++c)
    begin_[c + 1] += begin_[c];
  behind_.resize(binned_.size());
  std::vector<std::uint32_t>& next = queue_;
  next.assign(begin_.begin(), begin_.end() - 1);
  for (const auto& entry : binned_)
    behind_[next[entry.first]++] = entry.second;
  queue_.clear();
}

void PlaneCrossings::seed()
{
  queue_.clear();
  taken_.clear();
  for (std::size_t row = 0; row < rows_; ++row)
  {
    const float v = v0_ + (static_cast<float>(row) + 0.5f) * cell_;
    if (std::fabs(v) > half_height_)
      continue;
    for (std::size_t column = 0; column < columns_; ++column)
    {
      const float u = u0_ + (static_cast<float>(column) + 0.5f) * cell_;
      if (std::fabs(u) > half_width_)
        continue;
      const std::size_t cell = row * columns_ + column;
      visit_[cell] = grown;
      queue_.push_back(static_cast<std::uint32_t>(cell));
    }
  }
}

void PlaneCrossings::include(std::size_t cell)
{
  // The cell's centre: the plane's edge lies somewhere in the last cell crossed or the next.
  taken_.emplace_back(u0_ + (static_cast<double>(cell % columns_) + 0.5) * cell_,
                      v0_ + (static_cast<double>(cell / columns_) + 0.5) * cell_);
}

void PlaneCrossings::enclose(GrownExtent& extent)
{
  extent.grew = !taken_.empty();
  if (!extent.grew)
    return;
  for (const double u : { -half_width_, half_width_ })
    for (const double v : { -half_height_, half_height_ })
      taken_.emplace_back(u, v);
  convexHull(taken_, hull_);
  extent.rectangle = minAreaRectangle(hull_);
}

void applyGrownExtent(const GrownExtent& extent, ReflectiveObject& object)
{
  object.growth_capped = extent.reached_cap;
  const Rectangle2D& r = extent.rectangle;
  if (!extent.grew || !(r.area() > static_cast<double>(object.width) * object.height))
    return;
  if (!object.grown)
  {
    object.grown = true;
    object.patch_centre = object.centre;
    object.patch_width = object.width;
    object.patch_height = object.height;
  }
  const Eigen::Vector3f u = object.width_axis, v = object.height_axis;
  const Eigen::Vector3f along = (static_cast<float>(r.axis.x()) * u + static_cast<float>(r.axis.y()) * v).normalized();
  const Eigen::Vector3f across =
      (static_cast<float>(r.perpendicular().x()) * u + static_cast<float>(r.perpendicular().y()) * v).normalized();
  object.centre += static_cast<float>(r.centre.x()) * u + static_cast<float>(r.centre.y()) * v;
  // The more horizontal side is the width; the axes keep the patch's orientation (width x height
  // along the same normal) and point the same way as far as they can.
  const float tilt_difference = std::fabs(along.z()) - std::fabs(across.z());
  const bool along_is_width =
      std::fabs(tilt_difference) > kSameTilt ? tilt_difference < 0.0f : r.length >= r.breadth;
  Eigen::Vector3f width_axis = along_is_width ? along : across;
  Eigen::Vector3f height_axis = along_is_width ? across : along;
  if (width_axis.dot(u) < 0.0f)
    width_axis = -width_axis;
  if (width_axis.cross(height_axis).dot(u.cross(v)) < 0.0f)
    height_axis = -height_axis;
  object.width_axis = width_axis;
  object.height_axis = height_axis;
  object.width = static_cast<float>(along_is_width ? r.length : r.breadth);
  object.height = static_cast<float>(along_is_width ? r.breadth : r.length);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
