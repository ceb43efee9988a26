#include "ohm_mirror_detector3d/core/cone_labelling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>

#include "ohm_mirror_detector3d/core/block_box.h"
#include "ohm_mirror_detector3d/core/chain_cones.h"
#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/median.h"
#include "ohm_mirror_detector3d/core/merged_echoes.h"
#include "ohm_mirror_detector3d/core/parallel.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
Label surfaceLabel(ObjectType type)
{
  switch (type)
  {
    case ObjectType::mirror: return Label::reflectiveSurface;
    case ObjectType::glass: return Label::transparentSurface;
    default: return Label::errorSurface;
  }
}

Label behindLabel(ObjectType type)
{
  switch (type)
  {
    case ObjectType::mirror: return Label::behindReflective;
    case ObjectType::glass: return Label::behindTransparent;
    default: return Label::behindErrorS;
  }
}

// A point behind glass that lands on a surface the reflection maps onto itself (the floor seen
// through the pane, or the floor's reflection in it) is told by its intensity: a reflection comes
// back with the pane's reflectance (a few to a few tens of per cent below 75 deg incidence), a
// point seen through it with the pane's transmission (most of it). Against the surface seen
// directly where it lands, corrected for range (1 / r^2) and for the incidence on that surface
// (Lambert), a phantom keeps less than this share.
constexpr float kReflectedIntensityShare = 0.4f;

bool reflectedByIntensity(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                          const ReflectionTest& test, const Eigen::Vector3f& origin)
{
  // NaN (no evidence) compares false: the point stays what its geometry said.
  return landingIntensityShare(p, object.reflect(p), intensity, test, origin) < kReflectedIntensityShare;
}

// Behind glass, a point without evidence of its own (occluded, no return where it would land)
// may still be a reflection: of what the sensor cannot see (the ceiling above it, in a pane near
// by), or hidden from it. Its own brightness tells, against the object's: a reflection comes back
// with R^2 of the light (under 3 % for glass below 62 deg incidence), a point seen through with
// (1 - R)^2 (85 % and more). Where the object's sampled phantoms are at least
// kFaintPhantomContrast times fainter than what is seen through it (both: median intensity x
// range^2, object_type.cpp; what is seen through: TypeEvidence::seenThroughBrightness), a point
// fainter than their geometric mean is a reflection, a point at least as bright was seen through.
// Measured on random scenes 3000-3022 (32-ring lidar, the glass objects with both medians, points
// seen through): of the undecided points it takes for reflections, 1932 were phantoms, 138 real.
constexpr float kFaintPhantomContrast = 10.0f;
// And whatever the object's phantoms (its sampled "phantoms" may be real points landing on seen
// geometry by coincidence, as bright as what is seen through), a point fainter than this share
// of what is seen through it is a reflection: a point seen through glass keeps (1 - R)^2 of its
// light, a third of it even at 75 deg incidence, and the surfaces behind a pane differ in
// brightness by a few times, not twenty. Measured on random scene 5012 of the 128-ring lidar (a
// pane 0.5 m away, its reflections of the floor and ceiling out of the sensor's view): of the
// points behind it without evidence, the 2154 reflections kept 0.004-0.008 of the median seen
// through, the real ones 0.31 and more (10th percentile). On random scenes 5000-5029 it took
// 241 / 2154 / 1611 phantoms (64-, 128-, 32-ring lidars) and displaced 2 / 4 / 5 real points.
constexpr float kFaintAgainstSeenThrough = 0.05f;
// And whatever the contrast, a point at least as bright as what is seen through (where that is
// brighter than the phantoms, so no reflections themselves) was seen through: no reflection in
// glass comes back that bright. Without this, behind glass typed by its faint phantoms, whose
// points without evidence are reflections unless told otherwise, a contrast under
// kFaintPhantomContrast told nothing: the 32-ring lidar's random scene 41023 (a window 0.9 m away,
// phantoms 26 against 190 seen through) took 3093 real points of the ground outside, out of the
// sensor's view when reflected and at 1100-1250, for reflections. Measured: on make evaluate 566
// real points displaced fewer (32-ring lidar), on random scenes 39000-39024, 40000-40024 and
// 41000-41024 (all families) 193, 23 and 3093 fewer; no phantom moved.

// A pane grown beyond its surface-echo patch (glass_growth.h). Glass returns a surface echo only
// near perpendicular incidence, so the patch is all of it the sensor saw as a surface; beyond it
// the rays crossed the pane at an angle (the pane let them through, or reflected them). There:
// - a return on the plane is no echo of the pane (a frame, the wall, the floor it meets);
// - a point behind is the pane's only when no mirror's cone claims it (the growth reaches as far
//   as the rays cross the plane, into a metal panel or a mirror beside the pane in the same wall);
// - a point that lands on seen geometry is a reflection only when it kept less than
//   kGrownPaneReflectionShare of the brightness of what it lands on (landingIntensityShare).
//   Away from perpendicular incidence many more real points behind a pane land on seen geometry
//   by coincidence (a pane 1.25 m away from the rotating Hokuyo, random scene 5013: 442 of them),
//   while reflections in glass keep its reflectance, a few per cent below 60 deg incidence.
//   Measured on random scenes 4000-4019 (four scenes, the points that landed in grown parts):
//   reflections kept 0.01-0.24 (10th-90th percentile), real points 0.1-5 (medians 0.38-0.55).
//   On 4000-4019 and 5000-5029, 0.08 displaced within 2 % of the real points that no growth
//   displaces (0.15: up to 11 % more), and taking no reflection there at all left 1127 / 1924
//   more phantoms at a wrong place on the 128- and 32-ring lidars (5000-5029).
constexpr float kGrownPaneReflectionShare = 0.08f;
// The share needs the surface it lands on seen squarely: seen at grazing incidence (a wall edge-on
// at a corner with the ceiling) its Lambert correction divides by next to nothing. Beyond 75 deg
// incidence the point is kept. Measured on experiment2 (rotating Hokuyo, ideal physics: the glass
// door reflects nothing): 4 of the 5 real points behind it taken for reflections had landed on a
// wall seen at 83-89 deg.
constexpr float kMinGrownPaneLandingCosine = 0.25f;

// Whether a point behind a grown pane's part beyond its patch, landing where `test` says, kept so
// little of the brightness of what it lands on that it is a reflection in the pane.
bool faintReflectionInGrownPane(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                                const ReflectionTest& test, const Eigen::Vector3f& origin)
{
  const Eigen::Vector3f reflected = object.reflect(p);
  const Eigen::Vector3f to_landing = reflected - origin;
  const float range = to_landing.norm();
  if (!(range > 0.0f) || !(std::fabs(test.surface_normal.dot(to_landing)) >= kMinGrownPaneLandingCosine * range))
    return false;
  return landingIntensityShare(p, reflected, intensity, test, origin) < kGrownPaneReflectionShare;
}

// A surface echo comes back from glass only within a few degrees of perpendicular incidence, from
// a mirror within about twenty (the simulator: 4 and 20 degrees; DESIGN.md, "Where the paper's
// method runs out"). An object typed glass whose rectangle no beam meets within this angle of
// perpendicular, and whose echoes off the specular peak are mostly faint (faint_share, intensity
// evidence), is a layer of faint near echoes at oblique incidence: the reflection, in a pane at an
// angle that was not found (a glass door ajar, a window seen sideways), of a surface in the room,
// nearer than what the beams met through the pane. Its faint echoes beyond that angle are phantoms
// that cannot be put back (their pane is unknown): dropped as `error`. What is bright on its plane
// (a frame, a wall) and the points behind it (seen through the pane) stay. Measured with a
// temporary switch on held-out random scenes 42000-44024 (all families, 300 sweeps): 10.7k
// double-echo phantoms at a wrong place fewer (the rotating Hokuyo's random_43008 3165, the
// 128-ring lidar's random_43008 2663), 156 real points lost more; on make evaluate 2.0k fewer, 93
// more lost. Without the rectangle's condition, a pane's own haze seen at 1.7 m (the 32-ring
// lidar's random_43009, 2876 points) and a mirror typed glass lost their surface echoes.
constexpr float kMaxSpecularIncidenceDeg = 30.0f;
const float kMaxSpecularIncidenceCosine = std::cos(kMaxSpecularIncidenceDeg * static_cast<float>(M_PI) / 180.0f);
constexpr float kMinObliqueFaintShare = 0.5f;

// The cosine of the smallest incidence on the object's rectangle from `origin`: at the
// rectangle's point nearest to the foot of the perpendicular from the origin to its plane.
float largestIncidenceCosine(const ReflectiveObject& object, const Eigen::Vector3f& origin)
{
  const Eigen::Vector3f normal = object.plane.head<3>();
  const Eigen::Vector3f foot = origin - object.signedDistance(origin) * normal;
  const float a = std::clamp((foot - object.centre).dot(object.width_axis), -0.5f * object.width, 0.5f * object.width);
  const float b =
      std::clamp((foot - object.centre).dot(object.height_axis), -0.5f * object.height, 0.5f * object.height);
  const Eigen::Vector3f to_nearest = object.centre + a * object.width_axis + b * object.height_axis - origin;
  const float range = to_nearest.norm();
  return range > 0.0f ? std::fabs(normal.dot(to_nearest)) / range : 1.0f;
}

bool obliqueFaintSurface(const ReflectiveObject& object, const Eigen::Vector3f& origin)
{
  return object.type == ObjectType::glass && object.intensity.faint_share >= kMinObliqueFaintShare &&
         object.intensity.scale.reference > 0.0f && largestIncidenceCosine(object, origin) < kMaxSpecularIncidenceCosine;
}

// Whether an echo on an oblique faint surface's plane is one of its faint reflections: beyond the
// specular angle and fainter than a wall (kFaint, as the faint share counts them).
bool faintObliqueEcho(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                      const Eigen::Vector3f& origin)
{
  const Eigen::Vector3f normal = object.plane.head<3>();
  // NaN (at the origin, no intensity) compares false.
  return incidenceCosine(normal, p, origin) < kMaxSpecularIncidenceCosine &&
         brightnessOnPlane(object.intensity.scale, normal, p, intensity, origin) < kFaint;
}

// Two objects in one plane (3 deg, 10 cm at the second's centre): two detections of one pane.
bool samePlane(const ReflectiveObject& a, const ReflectiveObject& b)
{
  return a.sharesPlaneWith(b, 0.9986f, 0.1f);
}

// A grown pane's surface-echo patch (with the cone's margin), for the rules above; `grown` is
// false for every other object.
struct PanePatch
{
  bool grown = false;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f width_axis = Eigen::Vector3f::UnitX();
  Eigen::Vector3f height_axis = Eigen::Vector3f::UnitY();
  float half_width = 0.0f, half_height = 0.0f;

  PanePatch() = default;
  PanePatch(const ReflectiveObject& object, float margin)
    : grown(object.grown && object.type == ObjectType::glass)
    , centre(object.patch_centre)
    , width_axis(object.width_axis)
    , height_axis(object.height_axis)
    , half_width(0.5f * object.patch_width + margin)
    , half_height(0.5f * object.patch_height + margin)
  {
  }

  float area() const { return half_width * half_height; }

  // Whether a ray that crosses the pane's plane at `crossing` (ConeHit::crossing, the cone's own)
  // crosses it beyond the patch; false for an object not grown. (A pane grows only with the
  // sensor clear of its surface band, PlaneCrossings::build, so every point its cone holds has
  // its crossing on the ray.)
  bool beyond(const Eigen::Vector3f& crossing) const
  {
    if (!grown)
      return false;
    const Eigen::Vector3f offset = crossing - centre;
    return !(std::fabs(offset.dot(width_axis)) <= half_width && std::fabs(offset.dot(height_axis)) <= half_height);
  }
};

enum class Brightness
{
  untold,      // no intensity, or no contrast between the object's phantoms and what is seen through
  reflection,  // fainter than the geometric mean of the two, or far fainter than what is seen through
  seenThrough,  // at least as bright as that mean, or as what is seen through
};

// How bright (intensity x range^2) what is seen through an object is, and its reflections; NaN
// where nothing is known.
struct BrightnessReference
{
  float seen_through = std::numeric_limits<float>::quiet_NaN();
  float phantom = std::numeric_limits<float>::quiet_NaN();

  // The object's sampled points (TypeEvidence).
  static BrightnessReference of(const ReflectiveObject& object)
  {
    return BrightnessReference{ object.evidence.seenThroughBrightness(), object.evidence.phantom_brightness };
  }
};

// A point of this brightness against the reference.
Brightness tellBrightness(const BrightnessReference& reference, float brightness)
{
  // NaN (no intensity; nothing known seen through) compares false.
  if (!(brightness > 0.0f))
    return Brightness::untold;
  const float seen_through = reference.seen_through;
  if (brightness < kFaintAgainstSeenThrough * seen_through)
    return Brightness::reflection;
  const float phantom = reference.phantom;
  if (phantom > 0.0f && seen_through > phantom && brightness >= seen_through)
    return Brightness::seenThrough;
  if (!(phantom > 0.0f) || !(seen_through >= kFaintPhantomContrast * phantom))
    return Brightness::untold;
  return brightness < std::sqrt(phantom * seen_through) ? Brightness::reflection : Brightness::seenThrough;
}

Brightness brightnessBehind(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                            const Eigen::Vector3f& origin)
{
  return tellBrightness(BrightnessReference::of(object), rangeCompensatedBrightness(p, intensity, origin));
}

// A pane's type analysis tests a sample of the points behind its surface-echo patch; where too
// few of them landed on seen geometry or were seen through to tell how bright either is (a pane
// grown far beyond a small patch, most of its sample without evidence), the rule above had no
// reference and a reflection without evidence of its own was kept as seen through. Then the
// points of the pane's whole cone that did tell (their own test said phantom or transmitted, at
// least kMinConeBrightnessPoints of each) give the reference, and the points kept for want of
// evidence (occluded, no return) are told by it after the labelling. Only then: where the sample
// gave a reference, the cone's replaced it worse (its "phantoms" there include real points landing
// on seen geometry by coincidence; simulated on make evaluate's scenes: 118 phantoms taken for 772
// real points). Measured on random scenes 33000-33024 of the 32-ring lidar (random_33023: a pane
// 0.8 m away grown from 0.66 to 1.87 m wide, fewer than 10 of its 512 sampled points seen
// through): 3625 of its phantoms taken, 8 real points. It is rare: on make evaluate's 264 sweeps
// it moved 21 real points, on random scenes 34000-34024 of the 32- and 128-ring lidars nothing.
constexpr std::size_t kMinConeBrightnessPoints = 10;

// What the points of one object's cone that told said about brightness, and the points kept as
// seen through for want of evidence, to be told by it (BrightnessReference from the cone).
struct ConeBrightness
{
  bool wanted = false;  // a pane whose sample told no brightness
  std::vector<float> phantom, transmitted;
  struct Kept
  {
    std::uint32_t beam;
    float brightness;
  };
  std::vector<Kept> kept;  // beams of the echo the range labelled

  // Told what the point behind the object, labelled `label` by `outcome`, says (when wanted).
  void add(ReflectionOutcome outcome, Label label, std::size_t beam, float brightness)
  {
    if (!wanted || !(brightness > 0.0f))
      return;
    if (outcome == ReflectionOutcome::phantom)
      phantom.push_back(brightness);
    else if (outcome == ReflectionOutcome::transmitted)
      transmitted.push_back(brightness);
    else if ((outcome == ReflectionOutcome::occluded || outcome == ReflectionOutcome::noReturn) &&
             label == Label::behindTransparent)
      kept.push_back(Kept{ static_cast<std::uint32_t>(beam), brightness });
  }
};

// What the points behind an object said as a whole: its type, except for glass typed by its
// faint phantoms where the geometry said mirror (object_type.cpp: it showed reflections and
// nothing that could be proved real), whose points said "reflection".
ObjectType pointsSaid(const ReflectiveObject& object)
{
  return object.evidence.typed_by_dim_phantoms ? object.evidence.geometric_type : object.type;
}

// A point behind an object, by its own evidence first. A point without evidence of its own (it
// lands on a surface the reflection maps onto itself, where the sensor could not see, or where
// it saw nothing) takes what the object's other points said (pointsSaid): behind a mirror it is
// a phantom too, behind glass it is real, behind an unknown surface nobody can tell
// (behindErrorS).
Label behindLabel(const ReflectiveObject& object, ReflectionOutcome outcome)
{
  switch (outcome)
  {
    case ReflectionOutcome::phantom: return Label::behindReflective;
    case ReflectionOutcome::transmitted: return Label::behindTransparent;
    default:
    {
      const ObjectType said = pointsSaid(object);
      // Glass from unknown: nothing was decided either way; behind glass it is kept.
      return behindLabel(said == ObjectType::unknown ? object.type : said);
    }
  }
}

// Whether the points behind the object are kept as seen through where they tell nothing
// (behind glass).
bool keptAsReal(const ReflectiveObject& object)
{
  return behindLabel(object, ReflectionOutcome::ambiguous) == Label::behindTransparent;
}

// A mirror's plane at least this much further along a ray than a pane's is seen through the pane
// (claimOf); nearer, the two are one wall (a metal panel beside a pane), where the nearer
// surface takes the point as everywhere else [m]. Measured on random scene 16005 of the 128-ring
// lidar (a mirror 0.7 m behind a glass door): double-echo phantoms at a wrong place 13684 ->
// 11143, the mirror's surface echoes labelled behind the door before; on random scenes
// 16000-16024 and 17000-17024 no other sweep of any family changed by more than 45 points. Its
// cost (README, Stop 43): a pane's phantom plane that the phantom planes stage missed, typed
// mirror, takes the points behind it (make evaluate's random_29 and random_13).
constexpr float kMinDepthSeenThrough = 0.25f;
// And only a mirror at least this wide and high [m]: behind a pane the echoes of what is seen
// through it make small planar fragments, some typed mirror (random scenes 17011 and 17018 of the
// 128- and 32-ring lidars: 0.1 x 0.15 m to 0.1 x 1.07 m, in no mirror); taking the points behind
// them displaced 328 and 573 real points.
constexpr float kMinSeenThroughMirrorSide = 0.2f;

// Beams per block for the block test below: consecutive beams of one scan line lie close
// together, so a block's bounding box stays small, and 64 beams amortise the box tests.
constexpr std::size_t kBlockBeams = 64;
// A block that some cones may reach is split into sub-blocks of this many beams, each tested
// against those cones again: its smaller box culls most of them where a cone's edge crosses
// the block (map objects all round the sensor).
constexpr std::size_t kSubBlockBeams = 16;

// The evidence, asked for when the first point behind an object needs it (by whichever thread
// meets that point first; the others wait for it).
class LazyEvidence
{
public:
  explicit LazyEvidence(const std::function<const ReflectionEvidence&()>& source) : source_(source) {}
  const ReflectionEvidence& get()
  {
    std::call_once(asked_, [this]() { evidence_ = &source_(); });
    return *evidence_;
  }

private:
  const std::function<const ReflectionEvidence&()>& source_;
  std::once_flag asked_;
  const ReflectionEvidence* evidence_ = nullptr;
};

// What the labelling counted for one object (ReflectiveObject's counters of the points behind):
// each range of beams labelled side by side counts in its own, added up afterwards.
struct ConeTally
{
  std::size_t behind = 0, phantom = 0, transmitted = 0, ambiguous = 0, undecided = 0;

  void addTo(ReflectiveObject& object) const
  {
    object.behind_points += behind;
    object.phantom_points += phantom;
    object.transmitted_points += transmitted;
    object.ambiguous_points += ambiguous;
    object.undecided_points += undecided;
  }
};

// Conservative whole-block test for one object's vision cone: tells when no point inside an
// axis-aligned box can be on the surface of the object or behind it, so that the points of
// a block of beams need not be tested one by one. Whatever a point's exact test would
// answer, a box judged unaffected here holds no point the exact test calls onSurface or
// behind: the box must lie wholly in front of the surface band, or wholly outside one side
// face of the cone through a rectangle grown by a margin far larger than float rounding.
// Anything uncertain (sensor near the plane, non-finite numbers) is never culled.
class ConeBounds
{
public:
  ConeBounds(const ReflectiveObject& object, const Eigen::Vector3f& origin, float plane_threshold, float margin)
    : origin_(origin.cast<double>())
    , normal_(object.plane.head<3>().cast<double>())
    , offset_(object.plane[3])
  {
    const double origin_side = normal_.dot(origin_) + offset_;
    const Eigen::Vector3d centre = object.centre.cast<double>();
    const Eigen::Vector3d w = object.width_axis.cast<double>();
    const Eigen::Vector3d h = object.height_axis.cast<double>();
    // Rounding of the per-point test is of the order of 1e-6 of the coordinates; the grow
    // and band margins are a thousand times that.
    const double scale = (centre - origin_).norm() + object.width + object.height + std::fabs(offset_) +
                         origin_.cwiseAbs().maxCoeff() + centre.cwiseAbs().maxCoeff() + 1.0;
    const double grow = 1e-3 * scale;
    band_ = static_cast<double>(plane_threshold) + grow;
    // The per-point test extends the ray from the origin to the plane by origin_side /
    // (origin_side - point_side); with the sensor well outside the band that factor stays
    // below 2 for every point it judges, so its rounding stays small.
    usable_ = std::isfinite(scale) && origin_side > 2.0 * band_;
    // Far points make the per-point side and crossing less precise (relative to the sensor's
    // distance from the plane); boxes reaching further than this are not culled.
    reach_ = std::min(100.0 * origin_side, 100.0 * scale);
    if (!usable_)
      return;
    const double half_w = 0.5 * (object.width + object.footprint) + margin + grow;
    const double half_h = 0.5 * (object.height + object.footprint) + margin + grow;
    const std::array<Eigen::Vector3d, 4> corners = { centre - half_w * w - half_h * h, centre + half_w * w - half_h * h,
                                                     centre + half_w * w + half_h * h,
                                                     centre - half_w * w + half_h * h };
    for (std::size_t k = 0; k < 4; ++k)
    {
      // Face through the origin and one edge of the grown rectangle, normal towards the
      // inside of the cone.
      Eigen::Vector3d face = (corners[k] - origin_).cross(corners[(k + 1) % 4] - origin_);
      if (face.dot(centre - origin_) < 0.0)
        face = -face;
      faces_[k] = face;
      usable_ = usable_ && face.allFinite();
    }
  }

  // False when no point of the box [low, high] can be on or behind the object's surface.
  bool mayAffect(const Eigen::Vector3d& low, const Eigen::Vector3d& high) const
  {
    if (!usable_ || low.cwiseAbs().maxCoeff() > reach_ || high.cwiseAbs().maxCoeff() > reach_)
      return true;
    const Eigen::Vector3d centre = 0.5 * (low + high);
    const Eigen::Vector3d half = 0.5 * (high - low);
    // Every point of the box in front of the surface band.
    if (normal_.dot(centre) + offset_ - normal_.cwiseAbs().dot(half) > band_)
      return false;
    // Every point of the box outside one face of the (grown) cone.
    for (const Eigen::Vector3d& face : faces_)
      if (face.dot(centre - origin_) + face.cwiseAbs().dot(half) < 0.0)
        return false;
    return true;
  }

private:
  Eigen::Vector3d origin_;
  Eigen::Vector3d normal_;
  double offset_;
  double band_ = 0.0;
  double reach_ = 0.0;
  bool usable_ = false;
  std::array<Eigen::Vector3d, 4> faces_;
};

// The box of beams [from, to) of echo k, over their points that are not nanPoint.
BlockBox labelledBlockBox(const Sweep& sweep, const SweepLabels& labels, std::size_t k, std::size_t from,
                          std::size_t to)
{
  const Label* echo_labels = labels.echoes[k].data();
  return blockBox(sweep.echoes[k].points.data(), from, to,
                  [echo_labels](std::size_t i) { return echo_labels[i] != Label::nanPoint; });
}

// Whether the cone of `bounds` may reach a point of the block of `box` (always, when the block
// holds a non-finite point).
bool mayReach(const ConeBounds& bounds, const BlockBox& box)
{
  if (box.any_non_finite)
    return true;
  return !box.box.isEmpty() && bounds.mayAffect(box.box.min().cast<double>(), box.box.max().cast<double>());
}

// Counts a point behind the object by what it said (ReflectionOutcome).
void countBehind(ConeTally& tally, ReflectionOutcome outcome)
{
  ++tally.behind;
  switch (outcome)
  {
    case ReflectionOutcome::phantom: ++tally.phantom; break;
    case ReflectionOutcome::transmitted: ++tally.transmitted; break;
    case ReflectionOutcome::ambiguous: ++tally.ambiguous; break;
    default: ++tally.undecided; break;
  }
}

// Whether point p of beam `beam` (with `intensity`), behind `object` with its own test `test`, is
// one echo of the object's surface merged with a reflection in it (merged_echoes.h): faint against
// what is seen through the object, and landing on seen geometry when moved along its beam (seen
// through or occluded as measured), or landing exactly further along it (landing as measured).
// Then it is labelled a phantom and counted, and where its reflection's own echo lies is recorded.
bool takeMergedEcho(const ReflectionEvidence& evidence, const ReflectiveObject& object, const Eigen::Vector3f& p,
                    float intensity, std::size_t beam, const ReflectionTest& test, Label& label, ConeTally& tally,
                    std::vector<ObjectAssignment::MergedEcho>& merged_echoes)
{
  const ReflectionOutcome outcome = test.outcome;
  if ((outcome != ReflectionOutcome::transmitted && outcome != ReflectionOutcome::occluded &&
       outcome != ReflectionOutcome::phantom) ||
      !faintAsMergedReflection(object, p, intensity, evidence.sensorOrigin()))
    return false;
  const Eigen::Vector3f reflection = outcome == ReflectionOutcome::phantom ? mergedLanding(evidence, object, p, test) :
                                                                             mergedReflection(evidence, object, p);
  if (!reflection.allFinite())
    return false;
  merged_echoes.push_back(ObjectAssignment::MergedEcho{ static_cast<std::uint32_t>(beam), reflection });
  label = Label::behindReflective;
  countBehind(tally, ReflectionOutcome::phantom);
  return true;
}

// Which object a point belongs to: the nearest plane of the cones it lies in (on the surface or
// behind), with the rules for grown panes (PanePatch): beyond its patch a pane's claim yields to the
// nearest mirror's cone, then to another patch of the same pane that saw the point through its
// own rectangle, and among grown patches of one pane the widest takes it.
struct ConeClaim
{
  std::int32_t object = ObjectAssignment::kNoObject;
  ConeHit hit;
  bool beyond_patch = false;  // taken through a grown pane's part beyond its patch
  std::size_t affecting = 0;  // the cones the point lies in, a pane's beyond its patch not counted
                              // unless it took the point
};

ConeClaim claimOf(const Eigen::Vector3f& p, const std::vector<std::size_t>& reachable,
                  const std::vector<VisionCone>& cones, const std::vector<PanePatch>& patches,
                  const std::vector<ReflectiveObject>& objects)
{
  ConeClaim claim;
  claim.hit.plane_range = std::numeric_limits<float>::infinity();
  std::size_t beyond_patches = 0;
  std::int32_t nearest_mirror = ObjectAssignment::kNoObject, nearest_pane = ObjectAssignment::kNoObject;
  std::int32_t widest_grown = ObjectAssignment::kNoObject;
  ConeHit mirror_hit, pane_hit, grown_hit;
  mirror_hit.plane_range = pane_hit.plane_range = std::numeric_limits<float>::infinity();
  for (const std::size_t j : reachable)
  {
    const ConeHit hit = cones[j].locate(p);
    if (hit.relation != ConeRelation::onSurface && hit.relation != ConeRelation::behind)
      continue;
    const bool beyond = patches[j].beyond(hit.crossing);
    if (beyond && hit.relation == ConeRelation::onSurface)
      continue;  // no echo of the pane
    ++claim.affecting;
    beyond_patches += beyond ? 1 : 0;
    if (hit.plane_range < claim.hit.plane_range)
    {
      claim.object = static_cast<std::int32_t>(j);
      claim.hit = hit;
      claim.beyond_patch = beyond;
    }
    if (objects[j].type == ObjectType::mirror && hit.plane_range < mirror_hit.plane_range)
    {
      nearest_mirror = static_cast<std::int32_t>(j);
      mirror_hit = hit;
    }
    if (objects[j].type == ObjectType::glass && !beyond && hit.relation == ConeRelation::behind &&
        hit.plane_range < pane_hit.plane_range)
    {
      nearest_pane = static_cast<std::int32_t>(j);
      pane_hit = hit;
    }
    if (beyond && (widest_grown == ObjectAssignment::kNoObject ||
                   patches[j].area() > patches[static_cast<std::size_t>(widest_grown)].area()))
    {
      widest_grown = static_cast<std::int32_t>(j);
      grown_hit = hit;
    }
  }
  const auto object = [&](std::int32_t j) -> const ReflectiveObject& { return objects[static_cast<std::size_t>(j)]; };
  // A mirror seen through a pane (its plane clearly further along the ray than the pane's): the
  // pane let the beam through, the mirror turned it; the point is the mirror's (on its surface,
  // or its phantom), not a point seen through the pane.
  const auto mirrorSeenThrough = [&]() {
    return object(claim.object).type == ObjectType::glass &&
           mirror_hit.plane_range > claim.hit.plane_range + kMinDepthSeenThrough &&
           std::min(object(nearest_mirror).width, object(nearest_mirror).height) >= kMinSeenThroughMirrorSide;
  };
  if (nearest_mirror != ObjectAssignment::kNoObject && (claim.beyond_patch || mirrorSeenThrough()))
  {
    claim.object = nearest_mirror;
    claim.hit = mirror_hit;
    claim.beyond_patch = false;
  }
  else if (claim.beyond_patch && nearest_pane != ObjectAssignment::kNoObject &&
           samePlane(object(claim.object), object(nearest_pane)))
  {
    // Another detection of the same pane (a pane is often found as two patches) saw the point
    // through its own patch: its point, as without growth.
    claim.object = nearest_pane;
    claim.hit = pane_hit;
    claim.beyond_patch = false;
  }
  else if (claim.beyond_patch && widest_grown != claim.object &&
           samePlane(object(claim.object), object(widest_grown)))
  {
    // Grown over it from two patches of one pane: the plane of the wider patch (more surface
    // echoes) back-projects its reflections more exactly.
    claim.object = widest_grown;
    claim.hit = grown_hit;
  }
  // Taken by an object's own rectangle, the point is that object's as if no pane had grown over
  // it: a pane's claim beyond its patch does not make it a point that another object's reflection
  // may explain (which would leave its path unchecked). Measured on random scene 48 of the
  // 128-ring lidar: 6077 real points behind a pane typed mirror, seen through it by their paths,
  // were otherwise displaced.
  if (!claim.beyond_patch)
    claim.affecting -= beyond_patches;
  return claim;
}

// Labels the points of beams [block, block_end) of one echo, testing only the cones in
// `reachable` (every other cone is known to miss the block). Writes only those beams' labels and
// assignments, its own tallies (one per object) and merged echoes: ranges of beams are labelled
// side by side. A point on an object's surface is counted afterwards (countSurfaces).
void labelBlock(const EchoCloud& echo, std::size_t block, std::size_t block_end, const std::vector<std::size_t>& reachable,
                const std::vector<VisionCone>& cones, const std::vector<PanePatch>& patches, LazyEvidence& evidence,
                const ChainCones& chains, const std::vector<ReflectiveObject>& objects,
                std::vector<Label>& echo_labels, std::vector<std::int32_t>& echo_assignment,
                std::vector<ObjectAssignment::MergedEcho>& merged_echoes, std::vector<ConeTally>& tallies,
                std::vector<ConeBrightness>& brightness)
{
  for (std::size_t i = block; i < block_end; ++i)
  {
    Label& label = echo_labels[i];
    if (label == Label::nanPoint)
      continue;
    const ConeClaim claim = claimOf(echo.points[i], reachable, cones, patches, objects);
    const std::int32_t nearest = claim.object;
    const ConeHit& nearest_hit = claim.hit;
    const bool beyond_patch = claim.beyond_patch;
    const std::size_t affecting = claim.affecting;
    if (nearest == ObjectAssignment::kNoObject)
    {
      if (label != Label::error)
        label = Label::valid;
      continue;
    }
    const ReflectiveObject& object = objects[static_cast<std::size_t>(nearest)];
    ConeTally& tally = tallies[static_cast<std::size_t>(nearest)];
    echo_assignment[i] = nearest;
    if (nearest_hit.relation == ConeRelation::onSurface)
    {
      label = object.intensity.oblique_faint_surface &&
                      faintObliqueEcho(object, echo.points[i], echo.intensities[i], evidence.get().sensorOrigin()) ?
                  Label::error :
                  surfaceLabel(object.type);
    }
    else
    {
      // Behind glass an ambiguous point is kept as real: there the landing surface's normal is
      // worth a wider look (see ReflectionEvidence::test). Every point's path is checked.
      const bool kept_as_real = keptAsReal(object);
      const Eigen::Vector3f& origin = evidence.get().sensorOrigin();
      ReflectionTestOptions options;
      options.wide_normal = kept_as_real;
      // Behind another object too, the point may be that one's phantom; reflected to where it
      // would lie behind another object, the path may go on through that surface or be reflected
      // again (a reflection chain, reflection_chains.h). Either way its path proves nothing.
      if (affecting == 1)
      {
        const Eigen::Vector3f& p = echo.points[i];
        options.check_path =
            !chains.mayContinue(static_cast<std::size_t>(nearest), object.reflect(p), object.rayCrossing(origin, p));
      }
      const ReflectionTest test = evidence.get().test(object.plane, echo.points[i], object.landing_tolerance, options);
      const ReflectionOutcome outcome = test.outcome;
      // Only where the surface returned its echoes (a grown pane's patch; beyond it the rays met
      // the pane at an angle that returns next to nothing) can an echo be merged with it.
      if (!beyond_patch &&
          takeMergedEcho(evidence.get(), object, echo.points[i], echo.intensities[i], i, test, label, tally,
                         merged_echoes))
        continue;
      label = behindLabel(object, outcome);
      if (kept_as_real && outcome == ReflectionOutcome::ambiguous &&
          reflectedByIntensity(object, echo.points[i], echo.intensities[i], test, origin))
        label = Label::behindReflective;
      if (beyond_patch && label == Label::behindReflective &&
          (outcome == ReflectionOutcome::phantom || outcome == ReflectionOutcome::ambiguous) &&
          !faintReflectionInGrownPane(object, echo.points[i], echo.intensities[i], test, origin))
        label = Label::behindTransparent;
      if (kept_as_real && (outcome == ReflectionOutcome::occluded || outcome == ReflectionOutcome::noReturn) &&
          brightnessBehind(object, echo.points[i], echo.intensities[i], origin) == Brightness::reflection)
        label = Label::behindReflective;
      // Glass typed by its faint phantoms where its points' geometry said "reflection"
      // (pointsSaid): a point without evidence of its own is taken for a reflection, unless it is
      // as bright as what is seen through. Measured on random scenes 4000-4019 (32-ring lidar; a
      // pane 0.65 m away, the floor and the room behind it landing where the sensor could not
      // see, or on the floor): real points displaced 4841 -> 1564, phantoms left unchanged.
      if (!kept_as_real && object.type == ObjectType::glass && object.evidence.typed_by_dim_phantoms &&
          outcome != ReflectionOutcome::phantom && outcome != ReflectionOutcome::transmitted &&
          brightnessBehind(object, echo.points[i], echo.intensities[i], origin) == Brightness::seenThrough)
        label = Label::behindTransparent;
      brightness[static_cast<std::size_t>(nearest)].add(
          outcome, label, i, rangeCompensatedBrightness(echo.points[i], echo.intensities[i], origin));
      countBehind(tally, outcome);
    }
  }
}

// The points on each object's surface (those the labelling assigned to it with its surface
// label: no point behind gets one) and the mean intensity of those that have one, summed in beam
// order as one pass over the sweep.
void countSurfaces(const Sweep& sweep, const SweepLabels& labels, const ObjectAssignment& assignment,
                   std::vector<ReflectiveObject>& objects)
{
  // Without an object every beam is unassigned: nothing to count.
  if (objects.empty())
    return;
  std::vector<double> intensity_sums(objects.size(), 0.0);
  std::vector<std::size_t> intensity_counts(objects.size(), 0);
  std::vector<Label> surface_labels;
  for (const ReflectiveObject& object : objects)
    surface_labels.push_back(surfaceLabel(object.type));
  for (std::size_t k = 0; k < 2; ++k)
  {
    const std::vector<std::int32_t>& assigned = assignment.echoes[k];
    const std::vector<Label>& echo_labels = labels.echoes[k];
    const std::vector<float>& intensities = sweep.echoes[k].intensities;
    for (std::size_t i = 0; i < assigned.size(); ++i)
    {
      if (assigned[i] == ObjectAssignment::kNoObject)
        continue;
      const std::size_t j = static_cast<std::size_t>(assigned[i]);
      if (echo_labels[i] != surface_labels[j])
        continue;
      ++objects[j].surface_points;
      if (std::isfinite(intensities[i]))
      {
        intensity_sums[j] += intensities[i];
        ++intensity_counts[j];
      }
    }
  }
  for (std::size_t j = 0; j < objects.size(); ++j)
    objects[j].mean_surface_intensity = intensity_counts[j] > 0 ?
                                            static_cast<float>(intensity_sums[j] / intensity_counts[j]) :
                                            std::numeric_limits<float>::quiet_NaN();
}

// The boxes of blocks of kBlockBeams beams of each echo (their points that are not nanPoint), for
// culling the blocks a cone cannot reach: the objects' own cones and the borrowed ones alike (the
// labelling sets no point nanPoint, so the boxes hold for the whole of it).
struct EchoBlockBoxes
{
  std::array<std::vector<BlockBox>, 2> echoes;

  EchoBlockBoxes() = default;
  EchoBlockBoxes(const Sweep& sweep, const SweepLabels& labels)
  {
    const std::size_t beams = sweep.beamCount();
    for (std::size_t k = 0; k < 2; ++k)
      for (std::size_t from = 0; from < beams; from += kBlockBeams)
        echoes[k].push_back(labelledBlockBox(sweep, labels, k, from, std::min(beams, from + kBlockBeams)));
  }
};

// The points in the vision cones of the objects' phantom planes and of the surfaces seen through
// them (phantom_planes.h), and in no object's own: behind the object's plane, each is labelled by
// its own evidence against it (a phantom, or seen through). Without it, a point of a phantom
// plane's cone is kept (behindTransparent) where the object's points or the phantom plane's said
// glass, but never taken for a phantom (behindErrorS); beyond the phantom plane, the image of a
// wall, no reflection in the object shows anything (it would show what lies behind that wall):
// landing there proves nothing. A point on a surface seen through the object is kept
// (behindTransparent: the object let the sensor see it); beyond that surface, a point without
// evidence is none that the sensor could have seen directly (behindErrorS).
void labelBorrowedCone(const Sweep& sweep, const VisionCone& cone, const ConeBounds& bounds,
                       const EchoBlockBoxes& boxes, const ReflectiveObject& borrowed, bool seen_through,
                       std::size_t j, float plane_threshold, LazyEvidence& evidence,
                       std::vector<ReflectiveObject>& objects, SweepLabels& labels, ObjectAssignment& assignment)
{
  const ReflectiveObject& object = objects[j];
  ConeTally tally;
  const std::size_t beams = sweep.beamCount();
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < beams; ++i)
    {
      if (i % kBlockBeams == 0)
      {
        // A block the cone cannot reach is skipped whole (the same labels, fewer cone tests).
        if (!mayReach(bounds, boxes.echoes[k][i / kBlockBeams]))
        {
          i += kBlockBeams - 1;
          continue;
        }
      }
      Label& label = labels.echoes[k][i];
      if (label == Label::nanPoint || assignment.echoes[k][i] != ObjectAssignment::kNoObject)
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      const ConeRelation relation = cone.locate(p).relation;
      if ((relation != ConeRelation::onSurface && relation != ConeRelation::behind) ||
          !(object.signedDistance(p) < -plane_threshold))
        continue;
      const bool beyond = borrowed.signedDistance(p) < -plane_threshold;
      ReflectionTestOptions options;
      options.wide_normal = seen_through;
      const ReflectionTest test = evidence.get().test(object.plane, p, object.landing_tolerance, options);
      ReflectionOutcome outcome = test.outcome;
      if (!seen_through && outcome == ReflectionOutcome::phantom && beyond)
        outcome = ReflectionOutcome::noReturn;
      assignment.echoes[k][i] = static_cast<std::int32_t>(j);
      // A phantom plane may be made of the object's surface echoes merged with its reflections
      // (phantom_planes.cpp): those are back-projected from where their reflections land.
      if (!seen_through && !beyond &&
          takeMergedEcho(evidence.get(), object, p, sweep.echoes[k].intensities[i], i, test, label, tally,
                         assignment.merged_echoes[k]))
        continue;
      if (outcome == ReflectionOutcome::phantom || outcome == ReflectionOutcome::transmitted)
        label = behindLabel(object, outcome);
      else if (seen_through && outcome == ReflectionOutcome::ambiguous)
        label = reflectedByIntensity(object, p, sweep.echoes[k].intensities[i], test, evidence.get().sensorOrigin()) ?
                    Label::behindReflective :
                    Label::behindTransparent;
      else if (seen_through)
        label = beyond ? Label::behindErrorS : Label::behindTransparent;
      else
        label = behindLabel(object, outcome) == Label::behindTransparent ||
                        behindLabel(borrowed, outcome) == Label::behindTransparent ?
                    Label::behindTransparent :
                    Label::behindErrorS;
      countBehind(tally, outcome);
    }
  tally.addTo(objects[j]);
}

// The surface echoes of a pane's phantom planes are its reflections by the plane's verdict
// (phantom_planes.h). One kept as seen through for want of evidence of its own is labelled a
// reflection like the rest of its plane: its reflection lands where the sensor saw something
// nearer (the image of a side the sensor does not see, the back of a box in front of the pane),
// saw nothing, saw a surface the reflection maps onto itself, or saw a surface but the point was
// too bright for a reflection beyond the pane's patch. Only one that lands where the sensor
// looked through is kept. Measured on random scenes 0-49 (make evaluate's): double-echo phantoms
// at a wrong place 13.6 -> 11.9 % (rotating Hokuyo), 21.1 -> 20.9, 15.7 -> 15.5, 35.0 -> 34.5 %
// (64-, 128-, 32-ring lidars), no scene worse; real points behind glass labelled reflections up by
// 52 and 350 (rotating Hokuyo, 32-ring lidar: most in random_3, a glass wall 0.54 m away).
void labelPhantomPlaneEchoes(const Sweep& sweep, const std::vector<ReflectiveObject>& objects,
                             LazyEvidence& evidence, SweepLabels& labels, const ObjectAssignment& assignment)
{
  for (std::size_t j = 0; j < objects.size(); ++j)
  {
    const ReflectiveObject& object = objects[j];
    if (object.type != ObjectType::glass)
      continue;
    for (const ReflectiveObject& plane : object.phantom_planes)
      for (const PointRef& ref : plane.surface_inliers)
      {
        if (ref.echo > 1 || assignment.echoes[ref.echo][ref.beam] != static_cast<std::int32_t>(j))
          continue;
        Label& label = labels.echoes[ref.echo][ref.beam];
        if (label == Label::behindTransparent &&
            evidence.get()
                    .test(object.plane, sweep.echoes[ref.echo].points[ref.beam], object.landing_tolerance)
                    .outcome != ReflectionOutcome::transmitted)
          label = Label::behindReflective;
      }
  }
}

void labelPhantomPlaneCones(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, float plane_threshold,
                            float margin, const EchoBlockBoxes& boxes, LazyEvidence& evidence,
                            std::vector<ReflectiveObject>& objects, SweepLabels& labels, ObjectAssignment& assignment)
{
  for (std::size_t j = 0; j < objects.size(); ++j)
  {
    for (const bool seen_through : { false, true })
      for (const ReflectiveObject& borrowed :
           seen_through ? objects[j].seen_through_surfaces : objects[j].phantom_planes)
      {
        const VisionCone cone(borrowed, sensor_origin, plane_threshold, margin);
        const ConeBounds bounds(borrowed, sensor_origin, plane_threshold, margin);
        labelBorrowedCone(sweep, cone, bounds, boxes, borrowed, seen_through, j, plane_threshold, evidence, objects,
                          labels, assignment);
      }
  }
}
}  // namespace

void ObjectAssignment::reset(std::size_t beam_count)
{
  for (std::vector<std::int32_t>& objects : echoes)
    objects.assign(beam_count, kNoObject);
  for (std::vector<MergedEcho>& merged : merged_echoes)
    merged.clear();
}

ConeLabelling::ConeLabelling(const ConeLabellingConfig& config)
  : plane_threshold_(static_cast<float>(config.plane_threshold))
  , cone_margin_(static_cast<float>(config.cone_margin))
  , threads_(config.threads)
{
}

void ConeLabelling::apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                          const ReflectionEvidence& evidence, std::vector<ReflectiveObject>& objects,
                          SweepLabels& labels, ObjectAssignment& assignment) const
{
  apply(
      sweep, sensor_origin, [&evidence]() -> const ReflectionEvidence& { return evidence; }, objects, labels,
      assignment);
}

void ConeLabelling::apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                          const std::function<const ReflectionEvidence&()>& evidence_source,
                          std::vector<ReflectiveObject>& objects, SweepLabels& labels, ObjectAssignment& assignment) const
{
  LazyEvidence evidence(evidence_source);
  const std::size_t beams = sweep.beamCount();
  assignment.reset(beams);
  for (ReflectiveObject& object : objects)
  {
    object.surface_points = object.behind_points = object.phantom_points = object.transmitted_points =
        object.ambiguous_points = object.undecided_points = 0;
    object.intensity.oblique_faint_surface = obliqueFaintSurface(object, sensor_origin);
  }

  const float plane_threshold = plane_threshold_;
  const float margin = cone_margin_;
  std::vector<VisionCone> cones;
  std::vector<PanePatch> patches;
  cones.reserve(objects.size());
  patches.reserve(objects.size());
  for (const ReflectiveObject& object : objects)
  {
    cones.emplace_back(object, sensor_origin, plane_threshold, margin);
    patches.emplace_back(object, margin);
  }
  const ChainCones chains(objects, sensor_origin, plane_threshold, margin);
  std::vector<ConeBounds> bounds;
  bounds.reserve(objects.size());
  for (const ReflectiveObject& object : objects)
    bounds.emplace_back(object, sensor_origin, plane_threshold, margin);
  // Without an object there is no cone to cull (nor a borrowed one).
  const EchoBlockBoxes boxes = objects.empty() ? EchoBlockBoxes() : EchoBlockBoxes(sweep, labels);
  std::vector<std::size_t> all(objects.size());
  for (std::size_t j = 0; j < objects.size(); ++j)
    all[j] = j;

  // Each echo's blocks cut into ranges, a few per thread (ranges differ in how much lies behind
  // an object), each range labelled by one task with its own tallies and merged echoes. The
  // labels do not depend on the cut: a point's label reads only its own beam and the objects.
  const std::size_t blocks = (beams + kBlockBeams - 1) / kBlockBeams;
  const std::size_t ranges_per_echo = partsFor(blocks, threads_, 1);
  struct RangeResult
  {
    std::vector<ConeTally> tallies;
    std::vector<ObjectAssignment::MergedEcho> merged_echoes;
    std::vector<ConeBrightness> brightness;
  };
  std::vector<RangeResult> results(2 * ranges_per_echo);
  std::vector<ConeBrightness> no_brightness(objects.size());
  for (std::size_t j = 0; j < objects.size(); ++j)
    no_brightness[j].wanted = keptAsReal(objects[j]) && !(objects[j].evidence.seenThroughBrightness() > 0.0f);
  runTasks(results.size(), threads_, [&](std::size_t task, std::size_t) {
    const std::size_t k = task / ranges_per_echo;
    const std::size_t part = task % ranges_per_echo;
    const EchoCloud& echo = sweep.echoes[k];
    RangeResult& result = results[task];
    result.tallies.assign(objects.size(), ConeTally());
    result.brightness = no_brightness;
    // Objects whose cone the current block (sub-block) may reach, ascending (so that ties between
    // cones resolve as if every cone were tested).
    std::vector<std::size_t> reachable, sub_reachable;
    reachable.reserve(objects.size());
    sub_reachable.reserve(objects.size());
    // The cones of `candidates` that may reach the beams of `block_box` (every one of them when the
    // box of its labelled points is not finite).
    const auto cull = [&](const BlockBox& block_box, const std::vector<std::size_t>& candidates,
                          std::vector<std::size_t>& out) {
      out.clear();
      for (const std::size_t j : candidates)
        if (mayReach(bounds[j], block_box))
          out.push_back(j);
    };
    const std::size_t first_block = partBegin(blocks, ranges_per_echo, part);
    const std::size_t end_block = partBegin(blocks, ranges_per_echo, part + 1);
    for (std::size_t b = first_block; b < end_block; ++b)
    {
      const std::size_t block = b * kBlockBeams;
      const std::size_t block_end = std::min(beams, block + kBlockBeams);
      reachable.clear();
      if (!objects.empty())
        cull(boxes.echoes[k][b], all, reachable);
      if (reachable.empty())
      {
        labelBlock(echo, block, block_end, reachable, cones, patches, evidence, chains, objects, labels.echoes[k],
                   assignment.echoes[k], result.merged_echoes, result.tallies, result.brightness);
        continue;
      }
      for (std::size_t sub = block; sub < block_end; sub += kSubBlockBeams)
      {
        const std::size_t sub_end = std::min(block_end, sub + kSubBlockBeams);
        cull(labelledBlockBox(sweep, labels, k, sub, sub_end), reachable, sub_reachable);
        labelBlock(echo, sub, sub_end, sub_reachable, cones, patches, evidence, chains, objects, labels.echoes[k],
                   assignment.echoes[k], result.merged_echoes, result.tallies, result.brightness);
      }
    }
  });
  // In range order: the merged echoes in beam order, as one pass would have found them.
  for (std::size_t task = 0; task < results.size(); ++task)
  {
    const RangeResult& result = results[task];
    for (std::size_t j = 0; j < objects.size(); ++j)
      result.tallies[j].addTo(objects[j]);
    std::vector<ObjectAssignment::MergedEcho>& merged = assignment.merged_echoes[task / ranges_per_echo];
    merged.insert(merged.end(), result.merged_echoes.begin(), result.merged_echoes.end());
  }
  // A pane whose sample told no brightness: its cone's points that told give the reference, and
  // the points kept for want of evidence are told by it (kMinConeBrightnessPoints).
  for (std::size_t j = 0; j < objects.size(); ++j)
  {
    if (!no_brightness[j].wanted)
      continue;
    std::vector<float> phantom, transmitted;
    for (const RangeResult& result : results)
    {
      phantom.insert(phantom.end(), result.brightness[j].phantom.begin(), result.brightness[j].phantom.end());
      transmitted.insert(transmitted.end(), result.brightness[j].transmitted.begin(),
                         result.brightness[j].transmitted.end());
    }
    if (phantom.size() < kMinConeBrightnessPoints || transmitted.size() < kMinConeBrightnessPoints)
      continue;
    const BrightnessReference reference{ medianInPlace(transmitted), medianInPlace(phantom) };
    for (std::size_t task = 0; task < results.size(); ++task)
      for (const ConeBrightness::Kept& kept : results[task].brightness[j].kept)
        if (tellBrightness(reference, kept.brightness) == Brightness::reflection)
          labels.echoes[task / ranges_per_echo][kept.beam] = Label::behindReflective;
  }
  countSurfaces(sweep, labels, assignment, objects);
  labelPhantomPlaneCones(sweep, sensor_origin, plane_threshold, margin, boxes, evidence, objects, labels, assignment);
  labelPhantomPlaneEchoes(sweep, objects, evidence, labels, assignment);
  // The borrowed cones added their merged echoes after the objects' own: beam order again.
  for (std::vector<ObjectAssignment::MergedEcho>& merged : assignment.merged_echoes)
    std::sort(merged.begin(), merged.end(),
              [](const ObjectAssignment::MergedEcho& a, const ObjectAssignment::MergedEcho& b) { return a.beam < b.beam; });
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
