#include "ohm_mirror_detector3d/core/merged_echoes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// A merged echo (mergedReflection, below) is told from a real point just behind a pane by its
// brightness. Moved along their beams, real points just behind a pane land on seen geometry too
// (where the reflection of such a point falls close behind the sensor: a pane 0.5 m away, random
// scene 7 of the 128-ring lidar, 1154 real points seen through it taken for merged echoes). A
// merged echo comes back fainter than what is seen through the pane: the pane's surface echo and
// its reflection, a few per cent each, against (1 - R)^2 of the light. Measured on random scenes
// 0-19, the double-echo points behind glass within the separation of its plane and seen through
// by their own evidence: merged echoes kept 0.004-0.023 of the brightness seen through (10th-90th
// percentile, 128-ring lidar), real points 0.39-1.0. Without this gate (points seen through only)
// the real points displaced on random scenes 0-19 rose from 2954 and 23370 to 3227 and 24625 (64-
// and 128-ring lidars); with it (points seen through and occluded) they rose by 5 and 5, and the
// phantoms at a wrong place fell by 355 and 1603.
constexpr float kMergedEchoBrightnessShare = 0.25f;

// How far a bright reflection's merged echo lies short of it, as factors of the echo's distance
// behind the plane along its beam (mayBeMergedReflection). Measured: the 32-ring lidar's merged
// echoes of a plant and a person (single echoes, 0.5-0.7 m behind a tilted mirror 1.4 m away,
// random scene 48 of make evaluate) lay 0.04-0.11 m short of the reflections (factors 1.06-1.2).
// Reflected as measured, 1076 of the mirror's 8906 phantoms landed in the free space beside what
// they showed, seen through, and made the mirror glass.
constexpr float kMergeUndoFactors[] = { 1.1f, 1.2f, 1.3f };

// A point that lands as measured (within the landing tolerance) may still be a merged echo short of
// its reflection by less than the tolerance: back-projected as measured, up to a tolerance off.
// Its exact landing is taken when it lies at least this share of the tolerance further along the
// beam (beyond the range noise of a phantom that is no merged echo).
constexpr float kMinMergedShare = 0.25f;

// The most steps of the landing tolerance a merged reflection is searched in: the echo separation
// (0.9 m) over the smallest tolerance of a plausible sensor (a few centimetres) is some tens.
constexpr int kMaxMergeSteps = 200;

}  // namespace

bool faintAsMergedReflection(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                             const Eigen::Vector3f& origin)
{
  // NaN (no intensity, or nothing seen through the object) compares false.
  return rangeCompensatedBrightness(p, intensity, origin) <
         kMergedEchoBrightnessShare * object.evidence.seenThroughBrightness();
}

namespace
{
// Point p's beam and how far along it a reflection merged into p's echo may lie (what the echo
// separation leaves of p's distance behind the plane, along the ray), with the step of the
// search (the landing tolerance: a landing is that wide).
struct MergeReach
{
  Eigen::Vector3f along = Eigen::Vector3f::Zero();
  float behind = 0.0f;   // [m] p's distance behind the plane, along the beam
  float reach = 0.0f;    // [m] along the beam
  float step = 0.0f;     // [m]
  float longest = 0.0f;  // the farthest shift tried: the estimated separation may fall a little
                         // short of the sensor's (ReflectionEvidence::echoSeparation)
  bool usable = false;

  MergeReach(const ReflectionEvidence& evidence, const ReflectiveObject& object, const Eigen::Vector3f& p)
  {
    const float separation = evidence.echoSeparation();
    const Eigen::Vector3f& origin = evidence.sensorOrigin();
    const Eigen::Vector3f ray = p - origin;
    const float range = ray.norm();
    behind = range - (object.rayCrossing(origin, p) - origin).norm();
    reach = separation - behind;
    // A point in front of the plane holds no reflection in it; and the search below steps by the
    // landing tolerance, which must be positive (with a per_behind share, a point far in front of
    // the plane made it negative, and the search never ended).
    step = object.landing_tolerance.at(range, behind);
    usable = separation > 0.0f && range > 0.0f && behind >= 0.0f && reach > 0.0f && step > 0.0f;
    if (!usable)
      return;
    along = ray / range;
    longest = reach + 0.5f * step;
  }
};

// Only whether and where a shifted point lands counts here, so the test skips the wide normal and
// the path check. Landing on a surface the reflection maps onto itself (ambiguous) is landing
// too: what the echo is, its brightness said.
ReflectionTest plainTest(const ReflectionEvidence& evidence, const ReflectiveObject& object, const Eigen::Vector3f& p)
{
  return evidence.test(object.plane, p, object.landing_tolerance, ReflectionTestOptions());
}

bool lands(const ReflectionTest& test)
{
  return test.outcome == ReflectionOutcome::phantom || test.outcome == ReflectionOutcome::ambiguous;
}

// From a shift at which p lands (`best`, its test), the range difference there and half a step on
// give the shift where it vanishes (the surface landed on is locally flat: a secant step), kept
// when it lands closer. Returns the best shift found.
float refineShift(const ReflectionEvidence& evidence, const ReflectiveObject& object, const Eigen::Vector3f& p,
                  const MergeReach& reach, float best_shift, ReflectionTest best)
{
  const float probe_shift =
      best_shift + 0.5f * reach.step <= reach.longest ? best_shift + 0.5f * reach.step : best_shift - 0.5f * reach.step;
  const ReflectionTest probe = plainTest(evidence, object, p + probe_shift * reach.along);
  if (!lands(probe) || probe.range_difference == best.range_difference)
    return best_shift;
  const float secant = best_shift - best.range_difference * (probe_shift - best_shift) /
                                        (probe.range_difference - best.range_difference);
  if (std::fabs(probe.range_difference) < std::fabs(best.range_difference))
  {
    best_shift = probe_shift;
    best = probe;
  }
  if (secant > 0.0f && secant <= reach.longest && std::fabs(secant - best_shift) <= reach.step)
  {
    const ReflectionTest refined = plainTest(evidence, object, p + secant * reach.along);
    if (lands(refined) && std::fabs(refined.range_difference) < std::fabs(best.range_difference))
      best_shift = secant;
  }
  return best_shift;
}
}  // namespace

// One echo of the surface merged with a reflection in it. A sensor resolves two returns of a beam
// only this far apart (ReflectionEvidence::echoSeparation, 0.9 m for the dual-return lidars);
// nearer together they come back as one echo at a range between them, weighted by their
// intensities. Where a pane (or shiny metal) returns a surface echo and reflects the beam onto
// something less than that behind it, the echo lies short of the reflection by up to the
// separation: reflected across the plane it lands short of what it shows, where the sensor saw
// further (seen through, by its own evidence), or, behind what it shows from the sensor (a
// surface facing the pane), nearer (occluded). Moved along its beam by as much as
// the separation leaves (never beyond the surface echo's reach), such an echo lands on seen
// geometry; a point seen through does so only by coincidence, and is told by its brightness
// (kMergedEchoBrightnessShare). In the simulator's ground truth of random scenes 0-49, such
// merged echoes were 41 / 60 / 26 % of the double-echo phantoms left at a wrong place on the
// 64-, 128- and 32-ring lidars (3426 / 25238 / 13473 points; on the rotating Hokuyo, 0.3 m
// separation, 6 %): reflected as measured, none lands within 5 cm of what it shows.
//
// Coarse steps of the landing tolerance, laid back from the whole reach (where the reflection
// lies when the two returns were about as strong); the first that lands is refined (refineShift).
// Measured on the 64 x 600 frame of bench/side_by_side.py (169 merged echoes): the cone labelling
// took 9.3 ms without merged echoes, 13.0 ms with the cone labelling's own test options and a
// scan in tenths of a step, 9.7 ms so (the phantoms left on random scenes 0-19 within 0.1 point).
Eigen::Vector3f mergedReflection(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                                 const Eigen::Vector3f& p)
{
  const Eigen::Vector3f nowhere = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  const MergeReach reach(evidence, object, p);
  if (!reach.usable)
    return nowhere;
  // Counted, so that a step too small to change the shift cannot stall the search.
  float shift = reach.reach - reach.step * std::floor(reach.reach / reach.step);
  for (int steps = 0; steps <= kMaxMergeSteps && shift <= reach.reach + 1e-4f; ++steps, shift += reach.step)
  {
    if (!(shift > 0.0f))
      continue;
    const ReflectionTest test = plainTest(evidence, object, p + shift * reach.along);
    if (lands(test))
      return p + refineShift(evidence, object, p, reach, shift, test) * reach.along;
  }
  return nowhere;
}

bool mayBeMergedReflection(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                           const Eigen::Vector3f& p)
{
  const MergeReach reach(evidence, object, p);
  if (!reach.usable)
    return false;
  for (float factor : kMergeUndoFactors)
  {
    const ReflectionOutcome outcome =
        plainTest(evidence, object, p + (factor - 1.0f) * reach.behind * reach.along).outcome;
    if (outcome == ReflectionOutcome::phantom || outcome == ReflectionOutcome::ambiguous ||
        outcome == ReflectionOutcome::occluded)
      return true;
  }
  return false;
}

Eigen::Vector3f mergedLanding(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                              const Eigen::Vector3f& p, const ReflectionTest& measured)
{
  const Eigen::Vector3f nowhere = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  const MergeReach reach(evidence, object, p);
  if (!reach.usable || !lands(measured))
    return nowhere;
  const float shift = refineShift(evidence, object, p, reach, 0.0f, measured);
  return shift >= kMinMergedShare * reach.step ? Eigen::Vector3f(p + shift * reach.along) : nowhere;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
