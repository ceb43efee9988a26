// The per-point evidence behind a reflecting or transmitting surface: a point behind a plane,
// reflected across it, either lands on geometry the sensor saw in front (the point is a
// phantom of it), or lands where the sensor looked through (the point is real, seen through
// the surface), or the sensor could not have seen where it lands. The test is a range image
// by direction from the sensor: a direction index over every return of the sweep, at about
// the sweep's own angular step, built once per sweep and shared by every object (the type
// decision, the cone labelling, and any object stage that asks about points elsewhere on a
// plane).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/spatial_index.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// What the sweep says about a point behind a plane (its reflection q across the plane).
enum class ReflectionOutcome : std::uint8_t
{
  noReturn,     // no return in q's direction (nothing there, something that returns nothing, or out of view)
  occluded,     // what the sensor saw in q's direction is nearer than q: it could not see q
  phantom,      // q lies on what the sensor saw in its direction: the point is a reflection of it
  ambiguous,    // q lies on a surface that the reflection maps onto itself (a floor or a wall
                // perpendicular to the plane): a real point on that surface behind the plane
                // would land there just the same
  transmitted,  // what the sensor saw in q's direction is clearly beyond q: it looked through
                // where q would be, so the point is real, seen through the surface
};
constexpr int kReflectionOutcomeCount = 5;

const char* reflectionOutcomeName(ReflectionOutcome outcome);

struct ReflectionTest
{
  ReflectionOutcome outcome = ReflectionOutcome::noReturn;
  // Range of the surface seen in q's direction minus q's range [m] (NaN without a return).
  float range_difference = 0.0f;
};

class ReflectionEvidence
{
public:
  // Indexes every return of the sweep that is not nanPoint (a repeated single return once)
  // by its direction from sensor_origin. The angular step is the sweep's own: the median angle
  // between neighbouring returns along its rows and along its columns (the coarser of the
  // two; a sweep of one row, an unorganised cloud, takes the nearest return beyond a beam's row
  // neighbours for its column). A sweep with no neighbouring returns gets no index (every test
  // says noReturn).
  void build(const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& sensor_origin);

  // The coarser angular step of the sweep [rad], 0 when there is no index.
  float angularStep() const { return step_; }
  const Eigen::Vector3f& sensorOrigin() const { return origin_; }

  // The evidence for point p behind `plane` (n.x + d = 0, n a unit normal towards the sensor;
  // p with n.p + d < 0): reflected across the plane to q, is there a return at q's range in
  // q's direction (within tolerance.at(|q|, distance behind))? The range seen in q's
  // direction is interpolated between the nearest returns around it (exact on any plane,
  // also at grazing incidence) when they lie on one surface, else each is compared on its own.
  ReflectionTest test(const Eigen::Vector4f& plane, const Eigen::Vector3f& p, const LandingTolerance& tolerance) const;

private:
  // Calls visit(x) for every indexed return x (relative to the origin) in the cells that the
  // angular window of radius_ around `direction` touches, in the index's order, except returns
  // that are certainly outside the window (see kWindowSlack); `unit` is direction normalised.
  template <typename Visit>
  void forEachNear(const Eigen::Vector3f& direction, const Eigen::Vector3f& unit, Visit visit) const;

  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  float step_ = 0.0f;       // the sweep's coarser angular step [rad]
  float radius_ = 0.0f;     // angular window around a direction [rad]
  float cell_ = 0.0f;       // cube-map cell size (gnomonic units at a face centre)
  float inverse_cell_ = 0.0f;
  std::uint32_t cells_per_side_ = 0;
  SpatialIndex index_;      // returns relative to the origin, grouped by cube-map cell
  std::vector<float> squared_ranges_;  // |x|^2 of the index's returns, in its sorted order
  float window_cosine_bound_ = 0.0f;   // 1 + radius_^2 with slack (forEachNear)
  std::vector<float> row_angles_, column_angles_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
