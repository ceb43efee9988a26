#include "ohm_mirror_detector3d/core/intensity_evidence.h"

#include "ohm_mirror_detector3d/core/block_box.h"
#include "ohm_mirror_detector3d/core/median.h"
#include "ohm_mirror_detector3d/core/vision_cone.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

float median(std::vector<float>& values)
{
  return values.empty() ? kNaN : medianInPlace(values);
}

bool finite(const Eigen::Vector3f& p)
{
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

float clamped(float value, float limit)
{
  return std::max(-limit, std::min(limit, value));
}

// The object's plane and rectangle, for the test "on the object".
struct OnObject
{
  const ReflectiveObject& object;
  float plane_threshold;

  bool operator()(const Eigen::Vector3f& p) const
  {
    if (!finite(p) || std::abs(object.signedDistance(p)) > plane_threshold)
      return false;
    const Eigen::Vector3f rel = p - object.centre;
    return std::abs(rel.dot(object.width_axis)) <= object.width / 2 &&
           std::abs(rel.dot(object.height_axis)) <= object.height / 2;
  }
};
float medianAbsoluteDeviation(std::vector<float>& values)
{
  const float centre = median(values);
  for (float& v : values)
    v = std::abs(v - centre);
  return median(values);
}

// Whether most of the object's surface echoes lie behind another object's plane, within `reach`
// of its rectangle (IntensityEvidenceConfig::reach); only objects whose planes the object's centre
// lies at least kMinDepthBehindAnother behind count.
bool seenBehindAnother(const std::vector<ReflectiveObject>& objects, std::size_t index, const Sweep& sweep,
                       const Eigen::Vector3f& origin, float plane_threshold, float reach)
{
  const ReflectiveObject& object = objects[index];
  if (object.surface_inliers.empty())
    return false;
  std::vector<VisionCone> cones;
  for (std::size_t j = 0; j < objects.size(); ++j)
    if (j != index && objects[j].signedDistance(object.centre) < -kMinDepthBehindAnother &&
        std::fabs(objects[j].signedDistance(origin)) >= kMinSeenThroughPlaneDistance)
      cones.emplace_back(objects[j], origin, plane_threshold, reach);
  std::size_t behind = 0;
  for (const PointRef& ref : object.surface_inliers)
  {
    const Eigen::Vector3f& p = sweep.echoes[ref.echo].points[ref.beam];
    if (std::any_of(cones.begin(), cones.end(),
                    [&p](const VisionCone& cone) { return cone.locate(p).relation == ConeRelation::behind; }))
      ++behind;
  }
  return 2 * behind > object.surface_inliers.size();
}
}  // namespace

bool diffuseReflector(const IntensityFeatures& features)
{
  return features.bright_off_peak >= kMinDiffuseReflectorEchoes &&
         static_cast<float>(features.bright_off_peak) >= kDiffuseReflectorShare * static_cast<float>(features.off_peak) &&
         features.bright_backed_share >= kDiffuseReflectorBackedShare;
}

bool diffuseReflector(const ReflectiveObject& object)
{
  return std::min(object.width, object.height) >= kMinDiffuseReflectorSide &&
         object.evidence.surface_backed_share >= kDiffuseReflectorSurfaceBackedShare && diffuseReflector(object.intensity);
}

bool diffuseReflectorMayOverrule(const ReflectiveObject& object)
{
  const TypeEvidence& e = object.evidence;
  return object.type == ObjectType::glass && !e.typed_by_dim_phantoms &&
         e.transmitted_points <= kSeenThroughDominance * (e.phantom_points + e.undecided_points);
}

bool seenThroughLeaningPane(const ReflectiveObject& object, const IntensityEvidenceConfig& config)
{
  const TypeEvidence& e = object.evidence;
  // Real either way: seen through, or occluded where a phantom's light could not have come from.
  const std::size_t seen_through = e.transmitted_points + e.path_blocked_points;
  return object.type == ObjectType::unknown && object.intensity.log_odds < 0.0f &&
         seen_through >= config.min_seen_through && seen_through >= kSeenThroughLeaningDominance * e.phantom_points;
}

bool paneByItsEchoes(const IntensityFeatures& features)
{
  // NaN (too few echoes for a feature) compares false.
  return features.off_peak >= kMinDiffuseReflectorEchoes && features.faint_share < kMaxPaneFaintShare &&
         features.echo_ratio >= kMinPaneEchoRatio;
}

float FeatureModel::logLikelihoodRatio(float x) const
{
  const float a = (x - mirror) / sigma;
  const float b = (x - glass) / sigma;
  return 0.5f * (b * b - a * a);
}

IntensityScale intensityScale(const Sweep& sweep)
{
  // Every kReferenceStride-th beam, or sparser so that at most about kMaxScaleSamples returns are
  // sampled: a median needs no more, and on a 1080 x 400 sweep the sort and the logarithms of
  // every seventh return took 3-4 ms.
  const std::size_t stride = std::max(kReferenceStride, 2 * sweep.beamCount() / kMaxScaleSamples + 1);
  std::vector<float> raw, compensated;
  raw.reserve(2 * sweep.beamCount() / stride + 2);
  compensated.reserve(raw.capacity());
  for (const EchoCloud& echo : sweep.echoes)
    for (std::size_t beam = 0; beam < echo.size(); beam += stride)
    {
      const float intensity = echo.intensities[beam];
      const float range = echo.ranges[beam];
      if (std::isfinite(intensity) && intensity > 0.0f && std::isfinite(range) && range > 0.0f)
      {
        raw.push_back(intensity);
        compensated.push_back(intensity * range * range);
      }
    }
  IntensityScale scale;
  if (raw.empty())
    return scale;
  std::vector<float> log_raw(raw.size()), log_compensated(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
  {
    log_raw[i] = std::log(raw[i]);
    log_compensated[i] = std::log(compensated[i]);
  }
  scale.range_compensated = medianAbsoluteDeviation(log_raw) < medianAbsoluteDeviation(log_compensated);
  // The median raw signal * range^2: the intensities themselves when compensated.
  scale.reference = median(scale.range_compensated ? raw : compensated);
  return scale;
}

IntensityScale sweepIntensityScale(const Sweep& sweep, const std::vector<ReflectiveObject>& objects)
{
  if (!objects.empty() && objects.front().intensity.scale.reference > 0.0f)
    return objects.front().intensity.scale;
  return intensityScale(sweep);
}

IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, const IntensityScale& scale,
                                    const IntensityEvidenceConfig& config)
{
  SweepBlockBoxes block_boxes;
  sweepBlockBoxes(sweep, kIntensityBlockBeams, block_boxes);
  return intensityFeatures(sweep, sensor_origin, object, scale, config, block_boxes);
}

IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, const IntensityScale& scale,
                                    const IntensityEvidenceConfig& config, const SweepBlockBoxes& block_boxes)
{
  IntensityFeatures out;
  const float reference = scale.reference;
  if (!sweep.has_intensity || !(reference > 0.0f))
    return out;
  out.scale = scale;
  const OnObject on_object{ object, config.plane_threshold };
  const Eigen::Vector3f normal = object.plane.head<3>();
  const float cos_off_peak = std::cos(kOffPeakDeg * static_cast<float>(M_PI) / 180.0f);
  std::vector<float> faint, ratios;
  std::size_t bright_backed = 0, bright_near = 0;
  // What an echo on the object is in its beam: the far echo, or the near one, with or without a
  // far echo behind the plane.
  enum class Role
  {
    far,
    near,
    near_backed,
  };
  auto take = [&](const EchoCloud& echo, std::size_t beam, Role role) {
    const float range = echo.ranges[beam];
    const float intensity = echo.intensities[beam];
    if (!(range > 0.0f) || !std::isfinite(intensity))
      return;
    ++out.echoes;
    const float cos_incidence = std::abs(normal.dot(echo.points[beam] - sensor_origin)) / range;
    if (cos_incidence >= cos_off_peak)
      return;
    ++out.off_peak;
    const float lit = normalisedBrightness(scale, intensity, range, cos_incidence);
    if (lit >= kFaintMin && lit < kFaint)
      faint.push_back(lit);
    if (lit >= kFaint)
    {
      ++out.bright_off_peak;
      bright_near += role != Role::far ? 1 : 0;
      bright_backed += role == Role::near_backed ? 1 : 0;
    }
  };
  auto visit = [&](std::size_t beam) {
    const EchoCloud& a = sweep.echoes[0];
    const EchoCloud& b = sweep.echoes[1];
    const bool a_first = !(b.ranges[beam] < a.ranges[beam]);
    const EchoCloud& near = a_first ? a : b;
    const EchoCloud& far = a_first ? b : a;
    const bool near_on = on_object(near.points[beam]);
    const bool two = far.ranges[beam] - near.ranges[beam] > config.echo_threshold;
    if (near_on)
      take(near, beam,
           two && object.signedDistance(far.points[beam]) < -config.plane_threshold ? Role::near_backed : Role::near);
    if (two && on_object(far.points[beam]))
      take(far, beam, Role::far);
    if (near_on && two && near.intensities[beam] > 0.0f && far.intensities[beam] > 0.0f)
      ratios.push_back(scale.signal(far.intensities[beam], far.ranges[beam]) /
                       scale.signal(near.intensities[beam], near.ranges[beam]));
  };
  // Only the blocks of beams where either echo's box meets the box of the object's slab (its
  // rectangle, within plane_threshold of its plane): on a 1080 x 400 sweep a few hundred of 6750.
  // The features are medians and counts, the same in any order.
  Eigen::AlignedBox3f slab;
  for (const float u : { -0.5f, 0.5f })
    for (const float v : { -0.5f, 0.5f })
      for (const float w : { -1.0f, 1.0f })
        slab.extend(Eigen::Vector3f(object.centre + u * object.width * object.width_axis +
                                    v * object.height * object.height_axis + w * config.plane_threshold * normal));
  const std::size_t beams = sweep.beamCount();
  for (std::size_t block = 0; block < block_boxes[0].size(); ++block)
  {
    if (!block_boxes[0][block].intersects(slab) && !block_boxes[1][block].intersects(slab))
      continue;
    const std::size_t end = std::min(beams, (block + 1) * kIntensityBlockBeams);
    for (std::size_t beam = block * kIntensityBlockBeams; beam < end; ++beam)
      visit(beam);
  }
  if (bright_near > 0)
    out.bright_backed_share = static_cast<float>(bright_backed) / static_cast<float>(bright_near);
  float log_odds = 0.0f;
  if (out.off_peak >= kMinFeatureEchoes)
  {
    out.faint_share = static_cast<float>(faint.size()) / static_cast<float>(out.off_peak);
    log_odds += clamped(config.model.faint_share.logLikelihoodRatio(out.faint_share), kMaxFeatureLogOdds);
  }
  if (faint.size() >= kMinFeatureEchoes)
  {
    out.haze = median(faint);
    log_odds += clamped(config.model.haze.logLikelihoodRatio(std::log10(out.haze)), kMaxFeatureLogOdds);
  }
  if (ratios.size() >= kMinFeatureEchoes)
  {
    out.echo_ratio = median(ratios);
    log_odds += clamped(config.model.echo_ratio.logLikelihoodRatio(std::log10(out.echo_ratio)), kMaxFeatureLogOdds);
  }
  out.log_odds = clamped(log_odds, kMaxLogOdds);
  return out;
}

void IntensityEvidence::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence&,
                                SweepLabels&, std::vector<ReflectiveObject>& objects)
{
  if (objects.empty() || !sweep.has_intensity)
    return;
  const IntensityScale scale = sweepIntensityScale(sweep, objects);
  // The type analysis's boxes of this sweep when the pipeline gave it (the same blocks).
  static_assert(ObjectTypeAnalyzer::kBlockBoxBeams == kIntensityBlockBeams, "the same blocks");
  const SweepBlockBoxes* block_boxes = type_analyzer_ ? type_analyzer_->blockBoxes(sweep) : nullptr;
  SweepBlockBoxes own_boxes;
  if (block_boxes == nullptr)
  {
    sweepBlockBoxes(sweep, kIntensityBlockBeams, own_boxes);
    block_boxes = &own_boxes;
  }
  const Eigen::Vector3f origin = context.sensorOrigin();
  for (std::size_t i = 0; i < objects.size(); ++i)
  {
    ReflectiveObject& object = objects[i];
    object.intensity = intensityFeatures(sweep, origin, object, scale, config_, *block_boxes);
    const bool unknown = object.type == ObjectType::unknown;
    const bool reflector = (unknown || diffuseReflectorMayOverrule(object)) && diffuseReflector(object);
    const bool pane = object.type == ObjectType::mirror && paneByItsEchoes(object.intensity);
    const bool by_log_odds = !reflector && unknown && std::abs(object.intensity.log_odds) >= config_.type_log_odds;
    const bool seen_through = !reflector && !by_log_odds && seenThroughLeaningPane(object, config_);
    // Only an object that a rule would type is looked at against the others' cones.
    if (!(reflector || pane || by_log_odds || seen_through) ||
        seenBehindAnother(objects, i, sweep, origin, config_.plane_threshold, config_.reach))
      continue;
    if (reflector)
    {
      object.type = ObjectType::mirror;
      object.intensity.diffuse_reflector = true;
    }
    else if (pane)
    {
      object.type = ObjectType::glass;
      object.intensity.pane_by_echoes = true;
    }
    else if (seen_through)
    {
      object.type = ObjectType::glass;
      object.intensity.seen_through_pane = true;
    }
    else
    {
      object.type = object.intensity.log_odds > 0.0f ? ObjectType::mirror : ObjectType::glass;
      object.intensity.typed = true;
    }
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
