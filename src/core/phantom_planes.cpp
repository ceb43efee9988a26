#include "ohm_mirror_detector3d/core/phantom_planes.h"

#include <algorithm>
#include <tuple>

#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/merged_echoes.h"

namespace ohm_mirror_detector3d
{
namespace core
{
PhantomPlanes::PhantomPlanes(const PhantomPlaneConfig& config) : config_(config)
{
}

PhantomPlanes::Shares PhantomPlanes::shares(const Sweep& sweep, const Eigen::Vector3f& origin,
                                            const ReflectionEvidence& evidence, const ReflectiveObject& object,
                                            const ReflectiveObject& host, const IntensityScale* scale) const
{
  Shares result;
  const std::vector<PointRef>& echoes = object.surface_inliers;
  const float origin_side = host.signedDistance(origin);
  if (echoes.empty() || !(origin_side > 0.0f) || (config_.grown_hosts_only && !host.grown))
    return result;
  // A pane's surface echoes cover only its near-perpendicular patch; its phantom planes may hold
  // far more (random_29 on the rotating Hokuyo: 6321 against the patch's 623), so the echo ratio
  // bounds only a mirror's and an unknown object's.
  const bool host_is_pane = host.type == ObjectType::glass;
  // An object typed mirror (phantoms of its own landed on what they show) is no phantom plane of
  // an object whose type nothing decided: such a host is most often no reflecting surface at all.
  // make demo's sweep (experiment 1, 400 scans): the mixed pixels along the edge of the table
  // 0.25 m under the scanner make an `unknown` object, the mirror lies far behind its horizontal
  // plane, and reflected across it the mirror's echoes landed; the demo lost its mirror at 250, 350
  // and 400 scans. Behind a pane (the image of a box's hidden side) or another mirror (its image
  // in a mirror) an object typed mirror may still be one. make evaluate: no sweep changed.
  const bool mirror_behind_unknown = object.type == ObjectType::mirror && host.type == ObjectType::unknown;
  const bool within_echo_ratio =
      static_cast<float>(echoes.size()) <= config_.max_echo_ratio * static_cast<float>(host.surface_inliers.size());
  const bool may_be_phantoms = !mirror_behind_unknown && (host_is_pane || within_echo_ratio);
  // Nothing is seen through a mirror; and an object typed mirror showed reflections of its own
  // (a metal panel behind a glass wall, whose far echoes happened to land across the glass as well:
  // the 128-ring lidar's random_27) rather than being a wall seen through another.
  const bool may_be_seen_through = host.type != ObjectType::mirror && object.type != ObjectType::mirror;
  if (!may_be_phantoms && !may_be_seen_through)
    return result;
  const std::size_t stride = echoes.size() > kSampledEchoes ? echoes.size() / kSampledEchoes : 1;
  const std::size_t sampled = (echoes.size() + stride - 1) / stride;
  // Either share needs this many of the sample. The sampled echoes that could count at all (far
  // enough behind the host's plane) are found first, with no test of the evidence; once neither
  // share can reach it, the rest is not tested (the shares are then below min_share, not exact).
  const float needed = config_.min_share * static_cast<float>(sampled);
  // Just behind a pane (less than min_depth, more than kMinFaintDepth) an echo reflected across it
  // lands next to itself, so where it lands says nothing; its brightness does. Fainter than a
  // quarter of what the pane lets through (faintAsMergedReflection), it is the pane's surface echo
  // merged with a reflection, or the reflection of something close in front of the pane. Hesai
  // random_29: a person 0.45 m in front of a partition pane, imaged 0.2-0.35 m behind it, 562
  // such echoes typed mirror took the points behind them from the pane (815 double-echo phantoms
  // at a wrong place, 626 before the cone labelling let mirrors behind panes take points).
  // Not for an object of more than max_echo_ratio times the pane's echoes: a pane's own surface
  // echoes are faint too, and a pane's larger part just behind a speck of it is no reflection
  // (ouster random_43: 21298 echoes behind a 0.07 x 0.17 m speck of 488). Within that bound a real
  // pane just behind a false object is still taken for its reflection: a pane's surface echoes
  // are as faint against what it lets through as a reflection is, and their incidence did not tell
  // them apart either (velodyne random_19009 and 19021 each lost a pane so).
  // A pane grown to its extent (glass_growth.h) is measured by that: its surface echoes still cover
  // only its patch, and the phantom plane of something close in front of it may hold many more
  // (the rotating Hokuyo's random_7: 3638 faint echoes 0.26 m behind a partition pane of 567, the
  // reflection of what stands in front of it, typed mirror), but no rectangle larger than the pane.
  const bool within_grown_pane = host.grown && object.width * object.height <= host.width * host.height;
  const bool may_be_faint_reflections = host_is_pane && (within_echo_ratio || within_grown_pane);
  auto faintJustBehind = [&](const PointRef& ref) {
    if (!may_be_faint_reflections || ref.echo > 1)
      return false;
    const Eigen::Vector3f& p = sweep.echoes[ref.echo].points[ref.beam];
    const float depth = -host.signedDistance(p);
    return depth > kMinFaintDepth && depth <= config_.min_depth &&
           faintAsMergedReflection(host, p, sweep.echoes[ref.echo].intensities[ref.beam], origin);
  };
  // Just behind a pane (kMinFaintDepth .. min_depth), where landing proves nothing, an echo may
  // still be a surface seen through it: its beam's far echo, further behind, tells (below). Not
  // behind an object whose type nothing decided: such a host is most often no surface at all
  // (random scene 46017, 32-ring lidar: unknown specks took real surfaces behind them).
  auto seenThroughJustBehind = [&](const PointRef& ref) {
    if (!host_is_pane || !may_be_seen_through || ref.echo > 1)
      return false;
    const float depth = -host.signedDistance(sweep.echoes[ref.echo].points[ref.beam]);
    return depth > kMinFaintDepth && depth <= config_.min_depth;
  };
  // An echo with a grid cell (an input point without one is not in the direction index) at least
  // min_depth behind the host's plane, or faint just behind a pane, or just behind it at all when
  // it may be seen through it.
  auto behindHost = [&](const PointRef& ref) {
    return ref.echo <= 1 && (host.signedDistance(sweep.echoes[ref.echo].points[ref.beam]) < -config_.min_depth ||
                             faintJustBehind(ref) || seenThroughJustBehind(ref));
  };
  std::size_t behind = 0;
  for (std::size_t i = 0; i < echoes.size(); i += stride)
    behind += behindHost(echoes[i]) ? 1 : 0;
  if (static_cast<float>(behind) < needed)
    return result;
  // An echo of the host's surface merged with its reflection (merged_echoes.h) is the host's
  // phantom too: a plane of such echoes lies just behind a pane, short of the image of what it
  // shows (the 128-ring lidar's random_11: 3838 of them made a 0.49 x 1.59 m "mirror" behind a
  // pane, kept in place as its surface).
  // Only a pane's: moved along their beams, a real pane's surface echoes behind another object
  // also land (experiment 2's glass door, handed to a 0.28 x 0.19 m unknown speck in front of it on
  // the 64-ring lidar).
  const bool may_be_merged = host_is_pane;
  auto isMergedReflection = [&](const Eigen::Vector3f& p, float intensity) {
    return may_be_merged && faintAsMergedReflection(host, p, intensity, origin) &&
           mergedReflection(evidence, host, p).allFinite();
  };
  // The image of a side the sensor does not see (the back of a box or a person between the sensor
  // and a pane, reflected by the pane): reflected across the pane such a near echo lands just
  // behind the side of that thing the sensor does see (occluded, by at most max_hidden_depth), and
  // its beam's far echo, further behind the pane, is what the pane let through: neither the
  // pane's phantom nor the object's own (which would make the object a real mirror seen through
  // the pane). Both echoes of the beam lie behind the pane, one of them its reflection: the near
  // one. Only behind a pane: a mirror lets nothing through.
  // `far` is the beam's other echo (its far one when ref is the near one).
  auto isHiddenSideImage = [&](const PointRef& ref, const Eigen::Vector3f& p, const Eigen::Vector3f& far,
                               const ReflectionTest& near) {
    if (!host_is_pane || ref.echo != 0 || near.outcome != ReflectionOutcome::occluded ||
        !(near.range_difference < 0.0f && near.range_difference > -config_.max_hidden_depth))
      return false;
    return far.allFinite() && host.signedDistance(far) < host.signedDistance(p) - config_.min_depth &&
           evidence.test(host.plane, far, host.landing_tolerance).outcome != ReflectionOutcome::phantom &&
           evidence.test(object.plane, far, object.landing_tolerance).outcome != ReflectionOutcome::phantom;
  };
  // The far echo of a beam whose near echo lies behind the host, itself behind both planes.
  auto farBehindBoth = [&](const Eigen::Vector3f& far) {
    return may_be_seen_through && far.allFinite() && object.signedDistance(far) < -config_.min_depth &&
           host.signedDistance(far) < -config_.min_depth;
  };
  // Such a far echo landing when reflected across the host's plane: the host's reflection.
  auto farIsHostsPhantom = [&](const Eigen::Vector3f& far) {
    return farBehindBoth(far) &&
           evidence.test(host.plane, far, host.landing_tolerance).outcome == ReflectionOutcome::phantom;
  };
  // For a near echo just behind a pane: its far echo lands across the pane, on what the sensor saw
  // or on a surface the pane maps onto itself (a floor, a side wall: as often as not where such a
  // wall stands behind a partition), and not on what the sensor saw across the object's own plane.
  // Random scene 46008, rotating Hokuyo: a wall 0.17 m behind a partition's pane, seen through it,
  // had 74 of its far echoes land on such surfaces, 250 on what they show.
  auto farShowsSeenThroughJustBehind = [&](const Eigen::Vector3f& far) {
    if (!farBehindBoth(far))
      return false;
    const ReflectionOutcome across_host = evidence.test(host.plane, far, host.landing_tolerance).outcome;
    if (across_host != ReflectionOutcome::phantom && across_host != ReflectionOutcome::ambiguous)
      return false;
    return evidence.test(object.plane, far, object.landing_tolerance).outcome != ReflectionOutcome::phantom;
  };
  // A near echo behind a pane that lands on a surface the pane maps onto itself (a side wall that
  // runs through a partition) proves nothing; the plane through the few returns around where it
  // lands, a beam step apart, points anywhere where the range noise is a centimetre, and mostly
  // says the surface does not map onto itself. A reflection in glass is faint; an echo at least as
  // bright as a wall (normalisedBrightness at the object's incidence, kFaint) is no reflection in
  // the pane, and its landing surface's normal is taken from a ball of returns (wide_normal).
  // Random scene 48007: a metal panel (typed mirror) on such a wall behind a partition was taken
  // for the partition's phantom plane (the rotating Hokuyo: 4303 double-echo phantoms at a wrong
  // place, now 1880; the 128-ring lidar 1225 fewer). For every echo, without the brightness,
  // a pane's images of such walls were taken for real mirrors too (seed 46000: +2431; make
  // evaluate's random_7: +2614). False without intensities.
  auto asBrightAsAWall = [&](const Eigen::Vector3f& p, float intensity) {
    // NaN (at the origin, no intensity) compares false.
    return scale != nullptr && brightnessOnPlane(*scale, object.plane.head<3>(), p, intensity, origin) >= kFaint;
  };
  // The sample is visited in kPasses interleaved passes, each spread over the whole object: after
  // the first, a pair whose share there is under half of min_share is given up (most pairs tested
  // are no pair at all: random scene 29 on the 32-ring lidar, 30 objects, 220 pairs behind one
  // another, 18000 tests in 12 ms before).
  // phantoms: by where they land (or their merged reflection); faint: by brightness alone.
  std::size_t phantoms = 0, faint = 0, seen_through = 0, left = behind, tested = 0;
  // Whether neither share can reach min_share any more, even if every echo left counted.
  auto hopeless = [&]() { return static_cast<float>(std::max(phantoms + faint, seen_through) + left) < needed; };
  for (std::size_t pass = 0; pass < kPasses && !hopeless(); ++pass)
  {
    if (pass == 1 && static_cast<float>(std::max(phantoms + faint, seen_through)) < 0.5f * config_.min_share * tested)
      break;
    for (std::size_t i = pass * stride; i < echoes.size(); i += kPasses * stride)
    {
      const PointRef& ref = echoes[i];
      if (!behindHost(ref))
        continue;
      if (hopeless())
        break;
      const Eigen::Vector3f& p = sweep.echoes[ref.echo].points[ref.beam];
      --left;
      ++tested;
      // A real surface echo behind the host whose beam's far echo (behind both planes) is the
      // host's reflection and not the object's own was seen through the host. The tests are asked
      // in the order that spares the most: the far echo's against the host fails most often.
      const Eigen::Vector3f& far = sweep.echoes[1 - ref.echo].points[ref.beam];
      if (host.signedDistance(p) >= -config_.min_depth)
      {
        if (faintJustBehind(ref))
          ++faint;  // behind a pane, where may_be_phantoms holds
        else if (farShowsSeenThroughJustBehind(far))
          ++seen_through;
        continue;
      }
      const bool far_is_hosts_phantom = farIsHostsPhantom(far);
      if (!may_be_phantoms && !far_is_hosts_phantom)
        continue;
      ReflectionTestOptions near_options;
      near_options.wide_normal = host_is_pane && asBrightAsAWall(p, sweep.echoes[ref.echo].intensities[ref.beam]);
      const ReflectionTest near = evidence.test(host.plane, p, host.landing_tolerance, near_options);
      if (near.outcome == ReflectionOutcome::phantom ||
          (may_be_phantoms && (isMergedReflection(p, sweep.echoes[ref.echo].intensities[ref.beam]) ||
                               isHiddenSideImage(ref, p, far, near))))
        phantoms += may_be_phantoms ? 1 : 0;
      else if (far_is_hosts_phantom &&
               evidence.test(object.plane, far, object.landing_tolerance).outcome != ReflectionOutcome::phantom)
        ++seen_through;
    }
  }
  result.phantom = static_cast<float>(phantoms + faint) / static_cast<float>(sampled);
  result.landed = static_cast<float>(phantoms) / static_cast<float>(sampled);
  result.seen_through = static_cast<float>(seen_through) / static_cast<float>(sampled);
  return result;
}

void PhantomPlanes::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                            SweepLabels& /*labels*/, std::vector<ReflectiveObject>& objects)
{
  const std::size_t count = objects.size();
  if (count < 2)
    return;
  const Eigen::Vector3f origin = context.sensorOrigin();
  const IntensityScale scale = sweep.has_intensity ? sweepIntensityScale(sweep, objects) : IntensityScale();
  const IntensityScale* known_scale = scale.reference > 0.0f ? &scale : nullptr;
  // Left in the objects for the stages after this one (sweepIntensityScale).
  for (ReflectiveObject& object : objects)
    object.intensity.scale = scale;
  // (share, object, host, seen through, shown by brightness) of every pair at or above the share.
  std::vector<std::tuple<float, std::size_t, std::size_t, bool, bool>> pairs;
  for (std::size_t o = 0; o < count; ++o)
    for (std::size_t h = 0; h < count; ++h)
    {
      if (h == o)
        continue;
      const Shares pair = shares(sweep, origin, evidence, objects[o], objects[h], known_scale);
      if (pair.phantom >= config_.min_share && pair.phantom >= pair.seen_through)
        pairs.emplace_back(pair.phantom, o, h, false, pair.landed < config_.min_share);
      else if (pair.seen_through >= config_.min_share)
        pairs.emplace_back(pair.seen_through, o, h, true, false);
    }
  if (pairs.empty())
    return;
  // The clearest first: the pairs that geometry shows before those that need the brightness of
  // echoes just behind a pane (random_3 on the 32-ring lidar: a pane's phantom plane, itself all
  // faint, took faint specks beside it as its own phantoms, and was then no phantom plane of the
  // pane: 1602 more double-echo phantoms at a wrong place); then the larger share; between equal
  // shares the host with more surface echoes.
  std::sort(pairs.begin(), pairs.end(), [&objects](const auto& a, const auto& b) {
    if (std::get<4>(a) != std::get<4>(b))
      return std::get<4>(b);
    if (std::get<0>(a) != std::get<0>(b))
      return std::get<0>(a) > std::get<0>(b);
    return objects[std::get<2>(a)].surface_inliers.size() > objects[std::get<2>(b)].surface_inliers.size();
  });
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> host_of(count, kNone);
  std::vector<bool> is_host(count, false), seen_through(count, false);
  for (const auto& pair : pairs)
  {
    const std::size_t o = std::get<1>(pair), h = std::get<2>(pair);
    if (host_of[o] != kNone || is_host[o] || host_of[h] != kNone)
      continue;
    host_of[o] = h;
    is_host[h] = true;
    seen_through[o] = std::get<3>(pair);
  }
  for (std::size_t o = 0; o < count; ++o)
    if (host_of[o] != kNone)
      (seen_through[o] ? objects[host_of[o]].seen_through_surfaces : objects[host_of[o]].phantom_planes)
          .push_back(std::move(objects[o]));
  std::size_t kept = 0;
  for (std::size_t o = 0; o < count; ++o)
    if (host_of[o] == kNone)
    {
      if (kept != o)
        objects[kept] = std::move(objects[o]);
      objects[kept].id = static_cast<std::uint32_t>(kept);
      ++kept;
    }
  objects.resize(kept);
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
