#include "ohm_mirror_detector3d/core/intensity_evidence.h"

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
  if (values.empty())
    return kNaN;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
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
}  // namespace

float FeatureModel::logLikelihoodRatio(float x) const
{
  const float a = (x - mirror) / sigma;
  const float b = (x - glass) / sigma;
  return 0.5f * (b * b - a * a);
}

float intensityReference(const Sweep& sweep)
{
  std::vector<float> values;
  values.reserve(2 * sweep.beamCount() / kReferenceStride + 2);
  for (const EchoCloud& echo : sweep.echoes)
    for (std::size_t beam = 0; beam < echo.size(); beam += kReferenceStride)
    {
      const float value = echo.intensities[beam] * echo.ranges[beam] * echo.ranges[beam];
      if (std::isfinite(value) && value > 0.0f)
        values.push_back(value);
    }
  return median(values);
}

IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, float reference,
                                    const IntensityEvidenceConfig& config)
{
  IntensityFeatures out;
  if (!sweep.has_intensity || !(reference > 0.0f))
    return out;
  const OnObject on_object{ object, config.plane_threshold };
  const Eigen::Vector3f normal = object.plane.head<3>();
  const float cos_off_peak = std::cos(kOffPeakDeg * static_cast<float>(M_PI) / 180.0f);
  std::vector<float> faint, ratios;
  auto take = [&](const EchoCloud& echo, std::size_t beam) {
    const float range = echo.ranges[beam];
    const float intensity = echo.intensities[beam];
    if (!(range > 0.0f) || !std::isfinite(intensity))
      return;
    ++out.echoes;
    const float cos_incidence = std::abs(normal.dot(echo.points[beam] - sensor_origin)) / range;
    if (cos_incidence >= cos_off_peak)
      return;
    ++out.off_peak;
    const float lit = intensity * range * range / reference / std::max(cos_incidence, 1e-3f);
    if (lit >= kFaintMin && lit < kFaint)
      faint.push_back(lit);
  };
  for (std::size_t beam = 0; beam < sweep.beamCount(); ++beam)
  {
    const EchoCloud& a = sweep.echoes[0];
    const EchoCloud& b = sweep.echoes[1];
    const bool a_first = !(b.ranges[beam] < a.ranges[beam]);
    const EchoCloud& near = a_first ? a : b;
    const EchoCloud& far = a_first ? b : a;
    const bool near_on = on_object(near.points[beam]);
    const bool two = far.ranges[beam] - near.ranges[beam] > config.echo_threshold;
    if (near_on)
      take(near, beam);
    if (two && on_object(far.points[beam]))
      take(far, beam);
    if (near_on && two && near.intensities[beam] > 0.0f && far.intensities[beam] > 0.0f)
      ratios.push_back(far.intensities[beam] / near.intensities[beam]);
  }
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
  const float reference = intensityReference(sweep);
  const Eigen::Vector3f origin = context.sensorOrigin();
  for (ReflectiveObject& object : objects)
  {
    object.intensity = intensityFeatures(sweep, origin, object, reference, config_);
    if (object.type == ObjectType::unknown && std::abs(object.intensity.log_odds) >= config_.type_log_odds)
    {
      object.type = object.intensity.log_odds > 0.0f ? ObjectType::mirror : ObjectType::glass;
      object.intensity.typed = true;
    }
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
