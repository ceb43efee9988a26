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
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
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
  // For a point that lands (phantom, ambiguous): the intensity of the return seen nearest to q's
  // direction (NaN when the sweep has none) and the range it was seen at [m].
  float seen_intensity = std::numeric_limits<float>::quiet_NaN();
  float seen_range = std::numeric_limits<float>::quiet_NaN();
  // For a point that lands (phantom, ambiguous): the normal of the surface it lands on (zero
  // when unknown).
  Eigen::Vector3f surface_normal = Eigen::Vector3f::Zero();
  // Transmitted because the path a phantom's light would have taken (from where the beam met the
  // plane to q) pierces a surface the sensor saw (the point was occluded by it otherwise).
  bool path_blocked = false;
};

// Of the light that the surface a point lands on returns when seen directly, the share the point
// itself came back with: the point's intensity and the one seen where it lands
// (test.seen_intensity), each corrected for range (times r^2) and for its incidence on that
// surface (divided by the cosine, Lambert). A beam reflected by a surface of reflectance R comes
// back with R^2 of the light (R on the way out, R on the way back): a mirror's phantom with about
// 0.8 of it, shiny metal's with about a quarter, a reflection in glass with under 3 % below 60 deg
// incidence (Fresnel: 8 % reflected at perpendicular incidence, 16 % at 60 deg). A point seen
// through glass comes with most of it. NaN without the evidence (no intensities, no return or no
// surface normal where it lands). `reflected` is p reflected across the plane.
// The second looks ReflectionEvidence::test may take (each slower, and each asked for only where
// its measured benefit holds).
struct ReflectionTestOptions
{
  // Where the test window's few returns make out that the surface a point lands on does not map
  // onto itself, look again in a ball of returns around where it lands.
  bool wide_normal = false;
  // An occluded point whose phantom light would have had to pierce a surface the sensor saw is
  // real (transmitted, path_blocked).
  bool check_path = false;
};

float landingIntensityShare(const Eigen::Vector3f& p, const Eigen::Vector3f& reflected, float intensity,
                            const ReflectionTest& test, const Eigen::Vector3f& origin);

class ReflectionEvidence
{
public:
  // Indexes every return of the sweep that is not nanPoint (a repeated single return once)
  // by its direction from sensor_origin. The angular step is the sweep's own: the median angle
  // between neighbouring returns along its rows and along its columns (the coarser of the
  // two; a sweep of one row, an unorganised cloud, takes the nearest return beyond a beam's row
  // neighbours for its column). A sweep with no neighbouring returns gets no index (every test
  // says noReturn).
  // The index is built in ranges of returns on `threads` threads (core/parallel.h; the same
  // index for any number).
  void build(const Sweep& sweep, const SweepLabels& labels, const Eigen::Vector3f& sensor_origin, int threads = 1);

  // The coarser angular step of the sweep [rad], 0 when there is no index.
  float angularStep() const { return step_; }
  const Eigen::Vector3f& sensorOrigin() const { return origin_; }
  // The smallest distance between a beam's two echoes that the sensor resolves, as this sweep
  // shows it [m]: one of the smallest distances between the echoes of its double-echo beams (0
  // with too few of them). Returns of one beam closer together than that come back as one
  // echo at a range between them: where a partly specular surface (shiny metal) reflects the
  // beam onto something just in front of it, that echo lies behind the surface, within this
  // distance of it, and is neither the surface nor a phantom.
  float echoSeparation() const { return echo_separation_; }

  // The evidence for point p behind `plane` (n.x + d = 0, n a unit normal towards the sensor;
  // p with n.p + d < 0): reflected across the plane to q, is there a return at q's range in
  // q's direction (within tolerance.at(|q|, distance behind))? The range seen in q's
  // direction is interpolated between the nearest returns around it (exact on any plane,
  // also at grazing incidence) when they lie on one surface, else each is compared on its own.
  // A point that lands on a surface the reflection maps onto itself is ambiguous; options.wide_normal
  // checks a surface that the few returns of the window make out not to, in a ball of returns
  // around where the point lands (slower, and precise where the range noise is near the beam
  // spacing). The cone labelling asks for it behind glass, where an ambiguous point is kept as
  // real: measured on random scenes 2000-2035 (36 per family), the double-echo points behind
  // glass not labelled behindTransparent went from 39603 to 25124 on the 128-ring lidar, 6067
  // to 4906 on the 64-ring one. The type decision does not: with the precise normal, the
  // phantoms of mirrors on floors and side walls turn ambiguous, count no more as reflections,
  // and mirrors came out unknown (rotating Hokuyo: phantoms left 14.7 -> 29.8 %).
  // With options.check_path, a point occluded by a surface that the straight path from where its
  // beam met the plane to q crosses is transmitted (ReflectionTest::path_blocked): a phantom's
  // light came along that path. Only the cone labelling asks for it (see cone_labelling.cpp).
  ReflectionTest test(const Eigen::Vector4f& plane, const Eigen::Vector3f& p, const LandingTolerance& tolerance,
                      const ReflectionTestOptions& options = ReflectionTestOptions()) const;

  // Whether point p behind `plane`, reflected across it to q, lands clear of everything the
  // sensor saw in front of the plane: no return in the test's window around q's direction (not
  // only the nearest on each side, which the test compares) that lies more than `beyond` in front
  // of the plane is nearer than q's range plus `beyond`. False without an index.
  bool landsClear(const Eigen::Vector4f& plane, const Eigen::Vector3f& p, float beyond) const;

private:
  static constexpr std::size_t kMaxCandidates = 128;
  // A return in the window around a direction, in the direction's tangent basis (a, b: offsets
  // over depth).
  struct Candidate
  {
    float a, b, depth, range;
    Eigen::Vector3f point;  // relative to the origin
    std::size_t index;      // in the index's sorted order
  };
  // What the sensor saw around the direction of q (relative to the origin): the window's
  // returns, the nearest in each quadrant (corners), whether they lie on one surface and, when
  // they do, the range seen in q's direction (from the plane through at least three corners,
  // fitted, else the closest corner's).
  struct Sighting
  {
    Eigen::Vector3f along, e1, e2;  // q's direction and its tangent basis
    std::array<Candidate, kMaxCandidates> candidates;
    std::size_t count = 0;
    std::array<int, 4> corners = { -1, -1, -1, -1 };
    std::size_t corner_count = 0;
    int closest = -1;
    bool one_surface = false;
    bool fitted = false;
    Eigen::Vector3d fit = Eigen::Vector3d::Zero();  // 1 / depth = fit . (1, a, b)
    float seen = 0.0f;
    Eigen::Vector3f fittedNormal() const;
  };
  Sighting sight(const Eigen::Vector3f& q, float range, float tol) const;
  // Whether the straight path from `from` to q (both relative to the origin) pierces the
  // surface seen in front of q (at_q: q's sighting, occluded by a fitted surface).
  bool pathPiercesSeenSurface(const Eigen::Vector3f& from, const Eigen::Vector3f& q, const Sighting& at_q,
                              const LandingTolerance& tolerance, float behind) const;

  // Calls visit(x, j) (j: x's position in the index's sorted order) for every indexed return x
  // (relative to the origin) in the cells that the angular window of `radius` [rad] around
  // `direction` touches, in the index's order, except returns that are certainly outside the
  // window (see kWindowSlack); `unit` is direction normalised. With max_visits > 0 only every k-th return of those cells is looked at, k such
  // that about max_visits are (an even sample of a wide window).
  template <typename Visit>
  void forEachNear(const Eigen::Vector3f& direction, const Eigen::Vector3f& unit, float radius, std::size_t max_visits,
                   Visit visit) const;
  template <typename Run>
  void forEachCellRun(const Eigen::Vector3f& direction, float radius, Run run) const;
  // The normal of the surface the sensor saw at `seen_point` (relative to the origin, at range
  // `seen`), from a sample of the returns within a ball around it several beam spacings wide;
  // zero when they are too few or not one flat surface.
  Eigen::Vector3f surfaceNormalAround(const Eigen::Vector3f& seen_point, float seen) const;

  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  float step_ = 0.0f;       // the sweep's coarser angular step [rad]
  float radius_ = 0.0f;     // angular window around a direction [rad]
  float cell_ = 0.0f;       // cube-map cell size (gnomonic units at a face centre)
  float inverse_cell_ = 0.0f;
  std::uint32_t cells_per_side_ = 0;
  SpatialIndex index_;      // returns relative to the origin, grouped by cube-map cell
  std::vector<float> squared_ranges_;  // |x|^2 of the index's returns, in its sorted order
  std::vector<float> intensities_;     // their intensities (NaN: none), in the same order
  std::vector<float> indexed_intensities_;  // the same, in the order the returns were indexed
  std::vector<float> row_angles_, column_angles_;
  float echo_separation_ = 0.0f;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
