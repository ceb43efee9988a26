#include "ohm_mirror_detector3d/core/phantom_planes.h"

#include <algorithm>
#include <tuple>

namespace ohm_mirror_detector3d
{
namespace core
{
PhantomPlanes::PhantomPlanes(const PhantomPlaneConfig& config) : config_(config)
{
}

float PhantomPlanes::phantomShare(const Sweep& sweep, const Eigen::Vector3f& origin, const ReflectionEvidence& evidence,
                                  const ReflectiveObject& object, const ReflectiveObject& host) const
{
  const std::vector<PointRef>& echoes = object.surface_inliers;
  if (echoes.empty() || static_cast<float>(echoes.size()) >
                            config_.max_echo_ratio * static_cast<float>(host.surface_inliers.size()))
    return 0.0f;
  const float origin_side = host.signedDistance(origin);
  if (!(origin_side > 0.0f))
    return 0.0f;
  const std::size_t stride = echoes.size() > kSampledEchoes ? echoes.size() / kSampledEchoes : 1;
  std::size_t sampled = 0, phantoms = 0;
  for (std::size_t i = 0; i < echoes.size(); i += stride)
  {
    ++sampled;
    const PointRef& ref = echoes[i];
    if (ref.echo > 1)
      continue;  // an input point without a grid cell: not in the direction index
    const Eigen::Vector3f& p = sweep.echoes[ref.echo].points[ref.beam];
    const float point_side = host.signedDistance(p);
    if (!(point_side < -config_.min_depth))
      continue;
    if (evidence.test(host.plane, p, host.landing_tolerance).outcome == ReflectionOutcome::phantom)
      ++phantoms;
  }
  return static_cast<float>(phantoms) / static_cast<float>(sampled);
}

void PhantomPlanes::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                            SweepLabels& /*labels*/, std::vector<ReflectiveObject>& objects)
{
  const std::size_t count = objects.size();
  if (count < 2)
    return;
  const Eigen::Vector3f origin = context.sensorOrigin();
  // (share, phantom object, host) of every pair at or above the share.
  std::vector<std::tuple<float, std::size_t, std::size_t>> pairs;
  for (std::size_t o = 0; o < count; ++o)
    for (std::size_t h = 0; h < count; ++h)
    {
      if (h == o)
        continue;
      const float share = phantomShare(sweep, origin, evidence, objects[o], objects[h]);
      if (share >= config_.min_share)
        pairs.emplace_back(share, o, h);
    }
  if (pairs.empty())
    return;
  // The clearest first; between equal shares the host with more surface echoes.
  std::sort(pairs.begin(), pairs.end(), [&objects](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b))
      return std::get<0>(a) > std::get<0>(b);
    return objects[std::get<2>(a)].surface_inliers.size() > objects[std::get<2>(b)].surface_inliers.size();
  });
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> host_of(count, kNone);
  std::vector<bool> is_host(count, false);
  for (const auto& pair : pairs)
  {
    const std::size_t o = std::get<1>(pair), h = std::get<2>(pair);
    if (host_of[o] != kNone || is_host[o] || host_of[h] != kNone)
      continue;
    host_of[o] = h;
    is_host[h] = true;
  }
  for (std::size_t o = 0; o < count; ++o)
    if (host_of[o] != kNone)
      objects[host_of[o]].phantom_planes.push_back(std::move(objects[o]));
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
