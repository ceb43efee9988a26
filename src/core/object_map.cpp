#include "ohm_mirror_detector3d/core/object_map.h"

#include <algorithm>
#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// A sweep's evidence on one object, in [-1, 1] (+ mirror, - glass): +-1 where the geometry
// decided its type; where it did not, its intensity log-odds (intensity_evidence.h; 0 when that
// stage is off) as a share of the log-odds that types an object in one sweep, so that intensity
// evidence too weak to type in any one sweep still adds up over sweeps (an object the
// intensities typed votes +-1 this way too).
double vote(const ReflectiveObject& seen, double intensity_type_log_odds)
{
  if (!seen.intensity.typed)
  {
    if (seen.type == ObjectType::mirror)
      return 1.0;
    if (seen.type == ObjectType::glass)
      return -1.0;
  }
  const double share = static_cast<double>(seen.intensity.log_odds) / intensity_type_log_odds;
  return std::isfinite(share) ? std::max(-1.0, std::min(1.0, share)) : 0.0;
}

// What one sweep did to one map object: the sum of the votes of the sweep objects merged into it.
struct Sighting
{
  std::uint32_t id;
  double votes;
};

// Moves the origin onto the plane.
void projectOrigin(MapObject& object)
{
  object.origin -= (object.normal.dot(object.origin) + object.offset) * object.normal;
}
}  // namespace

void planeAxes(const Eigen::Vector3d& normal, Eigen::Vector3d& u, Eigen::Vector3d& v)
{
  const Eigen::Vector3d horizontal = normal.cross(Eigen::Vector3d::UnitZ());
  // Within ~6 degrees of horizontal the plane's own horizontal direction is ill-defined: x it is.
  if (horizontal.norm() > 0.1)
    u = horizontal.normalized();
  else
    u = (Eigen::Vector3d::UnitX() - normal.x() * normal).normalized();
  v = normal.cross(u);
  const double up = std::fabs(v.z()) > 1e-6 ? v.z() : v.y();
  if (up < 0.0)
  {
    u = -u;
    v = -v;
  }
}

void ObjectMap::setConfig(const ObjectMapConfig& config)
{
  if (config.cell_size != config_.cell_size)
    clear();
  config_ = config;
}

void ObjectMap::clear()
{
  objects_.clear();
  next_id_ = 0;
}

void ObjectMap::assign(std::vector<MapObject> objects, std::uint32_t next_id)
{
  objects_ = std::move(objects);
  next_id_ = next_id;
  for (const MapObject& object : objects_)
    next_id_ = std::max(next_id_, object.id + 1);
}

ObjectType ObjectMap::type(const MapObject& object) const
{
  if (object.mirror_log_odds >= config_.type_log_odds)
    return ObjectType::mirror;
  if (object.mirror_log_odds <= -config_.type_log_odds)
    return ObjectType::glass;
  return ObjectType::unknown;
}

std::array<Eigen::Vector2d, 4> ObjectMap::inCells(const MapObject& object,
                                                  const std::array<Eigen::Vector3d, 4>& corners) const
{
  Eigen::Vector3d u, v;
  planeAxes(object.normal, u, v);
  std::array<Eigen::Vector2d, 4> cells;
  for (std::size_t k = 0; k < 4; ++k)
  {
    const Eigen::Vector3d p = corners[k] - object.origin;
    cells[k] = Eigen::Vector2d(p.dot(u), p.dot(v)) / config_.cell_size;
  }
  return cells;
}

bool ObjectMap::touches(const MapObject& target, const std::array<Eigen::Vector3d, 4>& corners, PlaneGrid& cells) const
{
  const std::array<Eigen::Vector2d, 4> quad = inCells(target, corners);
  const int reach = static_cast<int>(std::ceil(config_.merge_gap / config_.cell_size));
  // Bounding boxes first: most map objects lie elsewhere on the plane or on another one.
  Eigen::Vector2d low = quad[0], high = quad[0];
  for (const Eigen::Vector2d& c : quad)
  {
    low = low.cwiseMin(c);
    high = high.cwiseMax(c);
  }
  if (!target.cells.empty() &&
      (high.x() + reach < target.cells.minI() || low.x() - reach > target.cells.maxI() + 1 ||
       high.y() + reach < target.cells.minJ() || low.y() - reach > target.cells.maxJ() + 1))
    return false;
  cells = PlaneGrid();
  bool touching = false;
  rasterizeQuad(quad, [&](int i, int j) {
    cells.set(i, j);
    touching = touching || target.cells.occupiedNear(i, j, reach);
  });
  return touching;
}

void ObjectMap::join(MapObject& kept, const MapObject& joined) const
{
  Eigen::Vector3d u, v, joined_u, joined_v;
  planeAxes(kept.normal, u, v);
  planeAxes(joined.normal, joined_u, joined_v);
  const double cell = config_.cell_size;
  joined.cells.forEach([&](int i, int j) {
    const Eigen::Vector3d p = joined.origin + ((i + 0.5) * joined_u + (j + 0.5) * joined_v) * cell - kept.origin;
    kept.cells.set(static_cast<int>(std::floor(p.dot(u) / cell)), static_cast<int>(std::floor(p.dot(v) / cell)));
  });
  const double limit = 1.0 / config_.forgetting;
  kept.mirror_log_odds = std::max(-limit, std::min(limit, kept.mirror_log_odds + joined.mirror_log_odds));
  kept.sweeps_seen = std::max(kept.sweeps_seen, joined.sweeps_seen);
  kept.plane_weight += joined.plane_weight;
}

void ObjectMap::observe(const std::vector<ReflectiveObject>& objects, const Eigen::Isometry3d& fixed_from_sweep,
                        std::vector<std::uint32_t>& merged_ids)
{
  merged_ids.assign(objects.size(), kNotMerged);
  std::vector<Sighting> sightings;
  const Eigen::Matrix3d rotation = fixed_from_sweep.linear();
  const double min_alignment = std::cos(config_.merge_angle);
  for (std::size_t k = 0; k < objects.size(); ++k)
  {
    const ReflectiveObject& seen = objects[k];
    const Eigen::Vector3d normal = (rotation * seen.plane.head<3>().cast<double>()).normalized();
    const double offset = seen.plane[3] - normal.dot(fixed_from_sweep.translation());
    const Eigen::Vector3d centre = fixed_from_sweep * seen.centre.cast<double>();
    const std::array<Eigen::Vector3f, 4> sweep_corners = seen.corners();
    std::array<Eigen::Vector3d, 4> corners;
    for (std::size_t c = 0; c < 4; ++c)
      corners[c] = fixed_from_sweep * sweep_corners[c].cast<double>();
    if (!normal.allFinite() || !std::isfinite(offset) || !centre.allFinite())
      continue;
    const double weight = std::max<double>(1.0, static_cast<double>(seen.surface_inliers.size()));

    std::vector<std::size_t> touching;
    PlaneGrid patch;
    for (std::size_t m = 0; m < objects_.size(); ++m)
    {
      const MapObject& candidate = objects_[m];
      if (std::fabs(normal.dot(candidate.normal)) < min_alignment ||
          std::fabs(candidate.normal.dot(centre) + candidate.offset) > config_.merge_distance)
        continue;
      PlaneGrid cells;
      if (touches(candidate, corners, cells))
      {
        if (touching.empty())
          patch = std::move(cells);
        touching.push_back(m);
      }
    }

    std::uint32_t id = 0;
    if (touching.empty())
    {
      MapObject created;
      created.id = id = next_id_++;
      created.normal = normal;
      created.offset = offset;
      created.origin = centre;
      projectOrigin(created);
      created.plane_weight = weight;
      const std::array<Eigen::Vector2d, 4> quad = inCells(created, corners);
      rasterizeQuad(quad, [&created](int i, int j) { created.cells.set(i, j); });
      created.footprint = seen.footprint;
      created.landing_tolerance = seen.landing_tolerance;
      objects_.push_back(std::move(created));
    }
    else
    {
      MapObject& target = objects_[touching.front()];
      id = target.id;
      target.cells.add(patch);
      // The plane: the weighted mean of what the sweeps saw (the new one turned to the map
      // object's side).
      const double side = normal.dot(target.normal) < 0.0 ? -1.0 : 1.0;
      const double total = target.plane_weight + weight;
      target.normal = (target.plane_weight * target.normal + weight * side * normal).normalized();
      target.offset = (target.plane_weight * target.offset + weight * side * offset) / total;
      target.plane_weight = total;
      projectOrigin(target);
      target.footprint = seen.footprint;
      target.landing_tolerance = seen.landing_tolerance;
      // The patch bridges further map objects: they become one, under the oldest id (the first).
      for (std::size_t t = touching.size(); t-- > 1;)
      {
        const std::uint32_t joined_id = objects_[touching[t]].id;
        join(objects_[touching.front()], objects_[touching[t]]);
        objects_.erase(objects_.begin() + static_cast<std::ptrdiff_t>(touching[t]));
        for (std::uint32_t& merged : merged_ids)
          merged = merged == joined_id ? id : merged;
        for (Sighting& sighting : sightings)
          sighting.id = sighting.id == joined_id ? id : sighting.id;
      }
    }
    merged_ids[k] = id;
    sightings.push_back(Sighting{ id, vote(seen, config_.intensity_type_log_odds) });
  }

  // Once per map object seen: forget a share, then add this sweep's vote.
  std::sort(sightings.begin(), sightings.end(), [](const Sighting& a, const Sighting& b) { return a.id < b.id; });
  for (std::size_t s = 0; s < sightings.size();)
  {
    double votes = 0.0;
    const std::uint32_t id = sightings[s].id;
    for (; s < sightings.size() && sightings[s].id == id; ++s)
      votes += sightings[s].votes;
    for (MapObject& object : objects_)
      if (object.id == id)
      {
        const double keep = 1.0 - config_.forgetting;
        object.mirror_log_odds = keep * object.mirror_log_odds + std::max(-1.0, std::min(1.0, votes));
        object.plane_weight *= keep;
        ++object.sweeps_seen;
      }
  }
}

ReflectiveObject ObjectMap::toReflectiveObject(const MapObject& object, const Eigen::Isometry3d& frame_from_fixed,
                                               const Eigen::Vector3f& sensor_origin) const
{
  Eigen::Vector3d u, v;
  planeAxes(object.normal, u, v);
  const double cell = config_.cell_size;
  const PlaneGrid& cells = object.cells;
  const double mid_i = cells.empty() ? 0.0 : 0.5 * (cells.minI() + cells.maxI() + 1);
  const double mid_j = cells.empty() ? 0.0 : 0.5 * (cells.minJ() + cells.maxJ() + 1);
  const Eigen::Vector3d centre = object.origin + (mid_i * u + mid_j * v) * cell;
  const Eigen::Matrix3d rotation = frame_from_fixed.linear();
  Eigen::Vector3d normal = rotation * object.normal;
  double offset = object.offset - normal.dot(frame_from_fixed.translation());
  if (normal.dot(sensor_origin.cast<double>()) + offset < 0.0)
  {
    normal = -normal;
    offset = -offset;
  }

  ReflectiveObject out;
  out.id = object.id;
  out.type = type(object);
  out.plane << normal.cast<float>(), static_cast<float>(offset);
  out.centre = (frame_from_fixed * centre).cast<float>();
  out.width_axis = (rotation * u).cast<float>();
  out.height_axis = (rotation * v).cast<float>();
  out.width = cells.empty() ? 0.0f : static_cast<float>((cells.maxI() - cells.minI() + 1) * cell);
  out.height = cells.empty() ? 0.0f : static_cast<float>((cells.maxJ() - cells.minJ() + 1) * cell);
  out.footprint = object.footprint;
  out.patch_centre = out.centre;
  out.patch_width = out.width;
  out.patch_height = out.height;
  out.landing_tolerance = object.landing_tolerance;
  return out;
}

bool ObjectMap::labelsFrom(const MapObject& object, const Eigen::Vector3d& sensor_origin) const
{
  if (std::fabs(object.normal.dot(sensor_origin) + object.offset) <= config_.plane_threshold || object.cells.empty())
    return false;
  const ReflectiveObject rectangle = toReflectiveObject(object, Eigen::Isometry3d::Identity(), Eigen::Vector3f::Zero());
  const double half_diagonal = 0.5 * std::hypot(rectangle.width, rectangle.height);
  return (rectangle.centre.cast<double>() - sensor_origin).norm() - half_diagonal < config_.max_range;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
