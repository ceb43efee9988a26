// Intensity evidence (issue 17): what the intensities of an object's echoes say about mirror
// against glass, beside the geometric evidence of the points behind it.
//
// Per object and sweep (IntensityFeatures on the object), from every return of either echo
// within plane_threshold of its plane and inside its rectangle:
// - normalised intensity q = intensity * range^2 / the sweep's median intensity * range^2 (a
//   diffuse surface's, roughly: the scanner's gain and units cancel), over cos(incidence);
// - faint_share: of the echoes beyond the specular peak (incidence > kOffPeakDeg), the share that
//   is faint (kFaintMin <= q < kFaint): a mirror's silvered back gives a faint haze over its whole
//   face (about 2 % of the reference in the simulator), glass almost nothing off the peak: what
//   lies on its plane there is its frame, as bright as a wall, or its own far fainter haze, seen
//   close by only;
// - haze: the median q of those faint echoes;
// - echo_ratio: the median far / near intensity over the beams whose near echo is on the object
//   and whose far echo lies behind it.
// The log-odds of mirror against glass sums, for each feature the sweep has (enough echoes), the
// log-likelihood ratio of two Gaussians (IntensityModel: log10 of haze and echo_ratio, faint_share
// as it is) with one spread per feature, each clamped to +-kMaxFeatureLogOdds; the sum to
// +-kMaxLogOdds, so that one sweep never decides alone beyond that and a multi-sweep map can add
// sweeps. An object the geometry left unknown is typed from it when |log-odds| reaches
// type_log_odds (IntensityFeatures::typed), unless most of its surface echoes lie behind another
// object (seen through a pane or in a reflection: see IntensityEvidenceConfig::reach).
//
// The model is a raw signal that falls with range squared (the UTM-30LX, an Ouster's `signal`).
// Drivers that publish a range-compensated reflectivity instead (many dual-return lidars) are
// recognised per sweep (IntensityScale) and their intensities divided by range squared first.
#pragma once

#include "ohm_mirror_detector3d/core/object_stage.h"
#include "ohm_mirror_detector3d/core/object_type.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
// A Gaussian per type of one feature, with a common spread.
struct FeatureModel
{
  float mirror = 0.0f;
  float glass = 0.0f;
  float sigma = 1.0f;

  // log p(x | mirror) - log p(x | glass).
  float logLikelihoodRatio(float x) const;
};

struct IntensityModel
{
  FeatureModel haze;         // log10(haze)
  FeatureModel faint_share;  // the share itself
  FeatureModel echo_ratio;   // log10(echo_ratio)
};

struct IntensityEvidenceConfig
{
  bool enabled = false;
  float plane_threshold = 0.05f;  // [m] an echo on the object's plane
  float echo_threshold = 0.05f;   // [m] a beam's far echo lies behind its near one (d_thres)
  float type_log_odds = 2.2f;     // |log-odds| that types an unknown object
  // [m] How far beside another object's rectangle a surface echo behind its plane may lie and
  // still count as seen through it or in it (growth_max_extent: a pane's patch may be that much
  // smaller than the pane, and the glass growth comes after this stage). An object whose surface
  // echoes mostly lie so is not typed by its intensities: they say as much about the pane's
  // transmission and reflection as about the object. Measured (stop 40, `make evaluate`, the
  // 57 sweeps that typing by intensity changed): typed by intensity without this rule, such
  // objects (a wall seen in a window as a phantom plane, a fragment of the wall behind a pane)
  // became mirrors and glass that took over the pane's cone: double-echo phantoms at a wrong
  // place 69765 -> 66534 of the 57 sweeps' (velodyne random_43: 397 -> 1055, ouster random_3:
  // 3376 -> 4146); with it, counted within the rectangle itself 66345, 0.5 m beyond 65409,
  // 1.5 m beyond 64807 (none of the 57 sweeps then loses more than 38).
  float reach = 1.5f;
  // Points seen through an object that make it glass when its intensities only lean that way
  // (icp_min_points; see seenThroughLeaningPane).
  std::size_t min_seen_through = 30;
  IntensityModel model;
};
// Only an object whose centre lies at least this far behind another's plane can be seen through it
// or in it. A fragment of the same surface a few degrees off its plane (an 8 x 15 cm patch beside a
// pane, random scene 13016 of the 128-ring lidar: the pane's centre 7 cm behind its plane) would
// otherwise claim, with the reach around it, most of the pane's echoes. Measured (stop 42):
// make evaluate's random_4 in every family (a metal panel beside a leaning mirror) and ouster
// random_48 leave 2,213 fewer double-echo phantoms at a wrong place and displace 24,500 fewer real
// points; held-out random scenes 14000-14024 the 64- and 32-ring lidars 3.0 and 3.4 points of
// per cent fewer, 15000-15024 0.03-0.04 more.
constexpr float kMinDepthBehindAnother = 0.25f;
// Nor through an object whose plane passes within this distance of the sensor [m]: seen edge-on,
// its rectangle grown by `reach` takes in the part of its plane next to the sensor, through which
// half of space is seen, and it would claim every surface behind its plane. Measured on held-out
// random scenes 42000-45024 (all families, 400 sweeps): a mirror whose plane passed 4 cm from the
// sensor (random_43012) had kept two metal panels behind it from being typed by their
// intensities in three families; 7 objects typed right that were not, none the other way;
// make evaluate unchanged.
constexpr float kMinSeenThroughPlaneDistance = 0.2f;

constexpr float kOffPeakDeg = 5.0f;
constexpr float kFaint = 0.1f;
// An echo's brightness against the sweep's reference, over the cosine of its incidence on the
// object's plane (never under 1e-3): a wall's diffuse echo is about 1, a mirror's haze about 0.02,
// an echo under kFaint is faint. NaN without a reference or an intensity.
inline float normalisedBrightness(const IntensityScale& scale, float intensity, float range, float cos_incidence)
{
  return scale.signal(intensity, range) * range * range / scale.reference / std::max(cos_incidence, 1e-3f);
}
// The cosine of the incidence, on a plane with unit `normal`, of the beam from `origin` to `p`
// (0 for p at the origin).
inline float incidenceCosine(const Eigen::Vector3f& normal, const Eigen::Vector3f& p, const Eigen::Vector3f& origin)
{
  const Eigen::Vector3f ray = p - origin;
  const float range = ray.norm();
  return range > 0.0f ? std::fabs(normal.dot(ray)) / range : 0.0f;
}
// The normalisedBrightness of the echo at `p` at its incidence on the plane with unit `normal`;
// NaN for p at the origin or without an intensity.
inline float brightnessOnPlane(const IntensityScale& scale, const Eigen::Vector3f& normal, const Eigen::Vector3f& p,
                               float intensity, const Eigen::Vector3f& origin)
{
  const float range = (p - origin).norm();
  if (!(range > 0.0f) || !std::isfinite(intensity))
    return std::numeric_limits<float>::quiet_NaN();
  return normalisedBrightness(scale, intensity, range, incidenceCosine(normal, p, origin));
}
constexpr float kFaintMin = 0.004f;
constexpr std::size_t kMinFeatureEchoes = 5;

// Shiny metal (a lift door, a cabinet front) is a partly specular reflector: lit like a wall
// wherever the beam meets it (a diffuse share of its light) and reflecting the rest, so beyond
// the specular peak its echoes are bright (lit >= kFaint) and most of them come with the
// reflection's echo behind the plane. Glass returns next to nothing off its peak (its haze is two
// to three orders fainter than a wall; what is bright on its plane there is its frame, with
// nothing behind it), a mirror a faint haze. The geometry often takes such metal for glass: its
// reflections land on the hidden faces of what stands in front of it (occluded, which without
// points seen through counts as real) or merge with its surface echo into one echo just behind
// it. Measured on random scenes 6000-6029 (all four sensor families, objects with >= 50 surface
// echoes in the ground truth and >= 20 off the peak): of 62 metal panels, bright off-peak echoes
// were >= 99 % of the off-peak ones for every one, backed by an echo behind for 32-100 % (>= 76 %
// for 59 of them); of 35 mirrors none had more than 33 % of its off-peak echoes bright, of 13
// panes none more than 76 % (a partition pane 1 m from the Hokuyo, 11434 points seen through it).
// Geometric glass and unknown objects with such echoes are typed mirror (diffuseReflector,
// diffuseReflectorMayOverrule); the guards below come from the false objects and panes of random
// scenes 7000-7024.
constexpr std::size_t kMinDiffuseReflectorEchoes = 20;
constexpr float kDiffuseReflectorShare = 0.9f;
// Since stop 50 0.75 (was 0.85): the panels' backed shares measured above (>= 76 % for 59 of 62).
// On held-out random scenes 42000-45024 (all families, 400 sweeps) with the surface-backed share
// below also at 0.75: four metal panels typed mirror that were glass (1614 double-echo phantoms
// at a wrong place fewer: hokuyo and velodyne random_42017, ouster random_42010, velodyne
// random_45016), no object the other way, no real point moved; make evaluate unchanged.
constexpr float kDiffuseReflectorBackedShare = 0.75f;
// Mixed pixels along a depth edge (the top of a cabinet: the near echo on its edge, the far one on
// the wall behind) are bright and backed too, but make a strip, not a panel: the rule needs a
// rectangle at least this wide both ways. Measured on random scenes 7000-7024: four such strips
// (7-28 cm by 42-72 cm, backed 0.60-0.81) were typed mirror with the rule at 0.5 and nothing else,
// and 1-36 real points behind each were back-projected (a 100 x 26 cm view of a metal panel now
// stays glass).
constexpr float kMinDiffuseReflectorSide = 0.3f;
// And a panel is seen over its whole face: of the points behind seen through its inside, nearly
// every one has its surface echo in front (TypeEvidence::surface_backed_share). A pane returns a
// surface echo only near perpendicular incidence; the bright echoes of a framed pane are its frame.
// Measured (random scenes 6000-6029 and 7000-7024): 98 of 103 metal panels at least 0.9 (the rest
// 0.73-0.86, with many merged echoes); a 3.6 x 1.8 m rectangle over a window of the 32-ring lidar
// whose off-peak echoes were 98 % bright and 96 % backed (its frame and the wall around it), 0.68.
// Since stop 50 0.75 (was 0.9; see kDiffuseReflectorBackedShare): between that window and most of
// the panels below 0.9.
constexpr float kDiffuseReflectorSurfaceBackedShare = 0.75f;
// Glass stands against this rule when the points seen through it are more than this many times
// those that landed on seen geometry or were not decided (a fence or a dusty pane: bright and
// backed, but what lies behind it is seen).
constexpr std::size_t kSeenThroughDominance = 2;
// Glass that reflects well (hit obliquely, or coated) shows the room as phantoms that land where
// they should, and nothing seen through it that the geometry can prove real: the geometry says
// mirror. Its surface echoes say otherwise. A mirror's silvered back gives a faint haze over its
// whole face, so most of its echoes off the specular peak are faint; on a pane's plane off the
// peak there is next to nothing but its frame and the wall around it, lit like a wall. And where
// a beam returned from the pane and from beyond it, the far echo is tens of times the near one,
// which is shiny metal's never (its diffuse echo outshines its reflection). Measured on random
// scenes 12000-12029 and 13000-13029 (all four sensor families, objects with >= 50 surface echoes
// in the ground truth, typed mirror by the geometry): 11 of the 12 panes had a faint share of
// 0-0.14 with an echo ratio of 26-597 (the twelfth had no echo off its peak); of 97 mirrors none
// had a faint share under 0.6, of 93 metal panels none an echo ratio over 2.2. Such an object is
// glass (paneByItsEchoes, IntensityFeatures::pane_by_echoes).
constexpr float kMaxPaneFaintShare = 0.3f;
constexpr float kMinPaneEchoRatio = 15.0f;
constexpr float kMaxFeatureLogOdds = 3.0f;
constexpr float kMaxLogOdds = 6.0f;
// A pane that the type analysis leaves unknown because the points seen through it lie outside the
// rectangle's inside (a sliver of surface echoes at a pane's edge or mullion, 4-20 cm wide: the
// inside is a quarter of that) still shows them in its cone: seen through, at least
// kSeenThroughLeaningDominance times as many as landed as phantoms, and at least
// IntensityEvidenceConfig::min_seen_through of them. Beside a mirror the sensor sees as much, so
// the geometry alone is no proof; with intensities that lean to glass (log-odds below zero, but
// short of type_log_odds) it is glass (seenThroughLeaningPane, IntensityFeatures::seen_through_pane).
// Measured (stop 45, make evaluate, the four families): of the objects left unknown, 11 panes
// qualified (log-odds -0.6 to -2.1), no mirror, no metal panel and no false object; the mirrors
// seen beside their edge (up to 171 points seen through, none landed) all had log-odds above 3.
constexpr std::size_t kSeenThroughLeaningDominance = 2;
// Every kReferenceStride-th beam (or fewer, kMaxScaleSamples) gives the sweep's reference
// intensity (a median needs no more).
constexpr std::size_t kReferenceStride = 7;

// The sweep's IntensityScale (reflective_object.h).
IntensityScale intensityScale(const Sweep& sweep);
// The same, as an earlier object stage of this sweep left it in the objects' intensity features
// (IntensityFeatures::scale: the phantom-plane stage works it out first), else worked out anew:
// on a 1080 x 400 sweep its strided samples cost 1.5 ms, a stage that needs it again would pay
// that twice.
IntensityScale sweepIntensityScale(const Sweep& sweep, const std::vector<ReflectiveObject>& objects);

// Beams per block of the sweep block boxes (block_box.h) intensityFeatures skips blocks by.
constexpr std::size_t kIntensityBlockBeams = 64;
// IntensityScale is worked out from at most about this many returns.
constexpr std::size_t kMaxScaleSamples = 16384;

// The features of a partly specular reflector (shiny metal; see kDiffuseReflectorShare).
bool diffuseReflector(const IntensityFeatures& features);
// The same of an object: its features, and a rectangle wide enough (kMinDiffuseReflectorSide).
bool diffuseReflector(const ReflectiveObject& object);
// Whether the geometry's type of the object leaves room for that rule: glass not typed by its dim
// phantoms, with no more points seen through than kSeenThroughDominance allows. (Unknown objects
// are open to every intensity rule.)
bool diffuseReflectorMayOverrule(const ReflectiveObject& object);
// The features of a pane the geometry took for a mirror (see kMaxPaneFaintShare): at least
// kMinDiffuseReflectorEchoes off the peak, hardly any of them faint, and far echoes far brighter
// than near ones.
bool paneByItsEchoes(const IntensityFeatures& features);
// An object the geometry left unknown whose cone shows what lies behind it (see
// kSeenThroughLeaningDominance) and whose intensities lean to glass without typing it.
bool seenThroughLeaningPane(const ReflectiveObject& object, const IntensityEvidenceConfig& config);

// The features and log-odds of one object (its intensity member is not touched).
IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, const IntensityScale& scale,
                                    const IntensityEvidenceConfig& config);
// The same with the sweep block boxes (of kIntensityBlockBeams beams) worked out once for
// all objects.
IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, const IntensityScale& scale,
                                    const IntensityEvidenceConfig& config, const SweepBlockBoxes& block_boxes);

class IntensityEvidence : public ObjectStage
{
public:
  // `type_analyzer` (optional): the pipeline's, whose block boxes of the sweep (beginSweep) this
  // stage then reads instead of working them out again (3-5 ms on a 1080 x 400 sweep).
  explicit IntensityEvidence(const IntensityEvidenceConfig& config, const ObjectTypeAnalyzer* type_analyzer = nullptr)
    : config_(config), type_analyzer_(type_analyzer)
  {
  }

  const char* name() const override { return "intensity_evidence"; }

  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

private:
  IntensityEvidenceConfig config_;
  const ObjectTypeAnalyzer* type_analyzer_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
