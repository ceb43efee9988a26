// The object map of the multi-sweep post-filter (post_filter.h): every mirror and pane seen so
// far, in a fixed frame (odom, map), kept over sweeps. A sweep's object is merged into a map
// object when it lies on the same plane (normals within merge_angle, its centre within
// merge_distance of the map object's plane) and its patch overlaps or touches (within
// merge_gap on the plane) what the map object covers; a patch that touches two map objects
// joins them. The extent is the union of the patches on the plane (plane_grid.h); the type is
// the sign of a log-odds of mirror against glass that every sweep seeing the object updates
// with its own type decision, after forgetting a share of what was known: a moved or replaced
// object is retyped within a bounded number of sweeps. Ids are handed out once and kept.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/plane_grid.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct ObjectMapConfig
{
  bool enabled = false;
  double merge_distance = 0.1;  // m: a sweep object's centre from the map object's plane
  double merge_angle = 0.1745;  // rad: between the normals
  double merge_gap = 0.1;       // m: patches this close on the plane touch
  double cell_size = 0.025;     // m: the extent's grid
  // Share of the log-odds (and of the plane's weight) forgotten each sweep the object is seen
  // in; the log-odds stays within +-1/forgetting.
  double forgetting = 0.1;
  // |log-odds| from which a map object is a mirror (positive) or glass (negative); a sweep's
  // decision adds +-1.
  double type_log_odds = 1.0;
  // The intensity log-odds that types an object in one sweep (intensity_type_log_odds): an
  // object the geometry left unknown adds its intensity log-odds over this, within +-1.
  double intensity_type_log_odds = 2.2;
  // A map object labels a sweep only when the sensor lies farther than this from its plane
  // (on the plane its vision cone is degenerate) and nearer than max_range to its centre.
  double plane_threshold = 0.05;
  double max_range = 60.0;
};

struct MapObject
{
  std::uint32_t id = 0;
  // Plane normal.x + offset = 0 in the fixed frame; the normal points to the side the object
  // was first seen from.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  double offset = 0.0;
  // Cell (0, 0) starts here (on the plane); the cells' axes follow from the normal (planeAxes).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  PlaneGrid cells;
  double plane_weight = 0.0;  // the surface echoes the plane is averaged over (with forgetting)
  double mirror_log_odds = 0.0;
  std::uint32_t sweeps_seen = 0;
  // From the last sweep that saw it: what the cone labelling needs beside the plane.
  float footprint = 0.0f;
  LandingTolerance landing_tolerance;
};

// The in-plane axes of a plane with unit normal `normal`: u horizontal (perpendicular to z; for
// a horizontal plane along x), v = normal x u pointing up (or along y).
void planeAxes(const Eigen::Vector3d& normal, Eigen::Vector3d& u, Eigen::Vector3d& v);

class ObjectMap
{
public:
  explicit ObjectMap(const ObjectMapConfig& config = ObjectMapConfig()) : config_(config) {}

  // New thresholds; the objects stay, unless the cell size changed (their cells would not fit).
  void setConfig(const ObjectMapConfig& config);
  const ObjectMapConfig& config() const { return config_; }

  const std::vector<MapObject>& objects() const { return objects_; }
  std::uint32_t nextId() const { return next_id_; }
  void clear();
  // Takes `objects` as the map (a loaded file); ids from `next_id` on are new.
  void assign(std::vector<MapObject> objects, std::uint32_t next_id);

  // merged_ids of a sweep object that could not be placed (a non-finite plane).
  static constexpr std::uint32_t kNotMerged = 0xffffffffu;

  // Merges the sweep's objects (in the sweep's frame, which is `fixed_from_sweep` in the fixed
  // frame) into the map; `merged_ids[k]` is the id of the map object object k is part of now
  // (kNotMerged for one that could not be placed).
  void observe(const std::vector<ReflectiveObject>& objects, const Eigen::Isometry3d& fixed_from_sweep,
               std::vector<std::uint32_t>& merged_ids);

  // The map object's type by its log-odds.
  ObjectType type(const MapObject& object) const;
  // The map object as a ReflectiveObject in `frame_from_fixed`'s frame (the identity: the fixed
  // frame): plane (normal towards `sensor_origin`), the bounding rectangle of its cells on its
  // axes (width along u, height along v), type, footprint, landing tolerance; the patch is the
  // rectangle, the counts zero.
  ReflectiveObject toReflectiveObject(const MapObject& object, const Eigen::Isometry3d& frame_from_fixed,
                                      const Eigen::Vector3f& sensor_origin) const;
  // Whether the map object may label a sweep taken from `sensor_origin` (in the fixed frame).
  bool labelsFrom(const MapObject& object, const Eigen::Vector3d& sensor_origin) const;

private:
  // The patch of `object` (fixed frame: normal `normal`) in map object `target`'s cells: true
  // when it overlaps or touches them; `cells` gets the patch's cells.
  bool touches(const MapObject& target, const std::array<Eigen::Vector3d, 4>& corners, PlaneGrid& cells) const;
  void join(MapObject& kept, const MapObject& joined) const;
  std::array<Eigen::Vector2d, 4> inCells(const MapObject& object, const std::array<Eigen::Vector3d, 4>& corners) const;

  ObjectMapConfig config_;
  std::vector<MapObject> objects_;
  std::uint32_t next_id_ = 0;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
