#include "ohm_mirror_detector3d/core/reflection_chains.h"

#include <algorithm>
#include <limits>

#include "ohm_mirror_detector3d/core/vision_cone.h"

namespace ohm_mirror_detector3d
{
namespace core
{
void ReflectionPaths::reset(std::size_t beam_count, std::size_t objects)
{
  objects_ = objects;
  nodes_.clear();
  for (std::size_t j = 0; j < objects; ++j)
    nodes_.push_back(Node{ kNoPath, static_cast<std::int32_t>(j), 1 });
  children_.assign(objects * objects, kNoPath);
  for (std::vector<std::int32_t>& paths : echoes_)
    paths.assign(beam_count, kNoPath);
  for (std::vector<ObjectAssignment::MergedEcho>& merged : merged_)
    merged.clear();
}

Eigen::Vector3f ReflectionPaths::reflectionEcho(std::size_t echo, std::size_t beam, const Eigen::Vector3f& p) const
{
  const std::vector<ObjectAssignment::MergedEcho>& merged = merged_[echo];
  if (merged.empty())
    return p;
  const auto found = std::lower_bound(
      merged.begin(), merged.end(), beam,
      [](const ObjectAssignment::MergedEcho& m, std::size_t b) { return static_cast<std::size_t>(m.beam) < b; });
  return found != merged.end() && found->beam == beam ? found->reflection : p;
}

std::int32_t ReflectionPaths::extend(std::int32_t parent, std::int32_t object)
{
  const Node& from = nodes_.at(static_cast<std::size_t>(parent));
  if (from.length >= kMaxReflections)
    return kNoPath;
  const std::size_t slot = static_cast<std::size_t>(parent) * objects_ + static_cast<std::size_t>(object);
  if (children_.at(slot) == kNoPath)
  {
    const std::int32_t node = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(Node{ parent, object, from.length + 1 });
    children_.resize(children_.size() + objects_, kNoPath);
    children_[slot] = node;
  }
  return children_[slot];
}

std::vector<std::int32_t> ReflectionPaths::mirrors(std::int32_t path) const
{
  std::vector<std::int32_t> chain;
  for (std::int32_t node = path; node != kNoPath; node = nodes_.at(static_cast<std::size_t>(node)).parent)
    chain.push_back(nodes_[static_cast<std::size_t>(node)].object);
  std::reverse(chain.begin(), chain.end());
  return chain;
}

Eigen::Vector3f ReflectionPaths::backProject(const std::vector<ReflectiveObject>& objects, std::size_t echo,
                                             std::size_t beam, const Eigen::Vector3f& p) const
{
  std::array<std::int32_t, kMaxReflections> chain;
  int length = 0;
  for (std::int32_t node = echoes_[echo][beam]; node != kNoPath; node = nodes_[static_cast<std::size_t>(node)].parent)
    chain[static_cast<std::size_t>(length++)] = nodes_[static_cast<std::size_t>(node)].object;
  Eigen::Vector3f position = length > 0 ? reflectionEcho(echo, beam, p) : p;
  while (length > 0)
    position = objects.at(static_cast<std::size_t>(chain[static_cast<std::size_t>(--length)])).reflect(position);
  return position;
}

ReflectionChains::ReflectionChains(const ReflectionChainConfig& config) : config_(config)
{
}

ReflectionChainCounts ReflectionChains::apply(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                              const ReflectionEvidence& evidence,
                                              const std::vector<ReflectiveObject>& objects,
                                              const ObjectAssignment& assignment, SweepLabels& labels,
                                              ReflectionPaths& paths) const
{
  ReflectionChainCounts counts;
  const std::size_t beams = sweep.beamCount();
  paths.reset(beams, objects.size());
  paths.setMergedEchoes(assignment.merged_echoes);
  std::vector<std::int32_t> mirrors;
  for (std::size_t j = 0; j < objects.size(); ++j)
    if (objects[j].type == ObjectType::mirror)
      mirrors.push_back(static_cast<std::int32_t>(j));
  const float threshold = config_.plane_threshold;
  const int max_reflections = config_.max_reflections;
  for (std::size_t k = 0; k < 2; ++k)
  {
    const std::vector<Eigen::Vector3f>& points = sweep.echoes[k].points;
    for (std::size_t i = 0; i < beams; ++i)
    {
      if (labels.echoes[k][i] != Label::behindReflective)
        continue;
      const std::int32_t first = assignment.echoes[k][i];
      if (first == ObjectAssignment::kNoObject)
        continue;
      std::int32_t path = first;
      const bool follow = max_reflections > 0 && !mirrors.empty() &&
                          !(mirrors.size() == 1 && mirrors[0] == first);
      if (!follow)
      {
        paths.setPath(k, i, path);
        continue;
      }
      // The path so far is a straight ray from `apex` (the sensor's image in the mirrors passed)
      // through `crossing` (where it left the last mirror) to `point`, which lies behind `mirror`.
      const ReflectiveObject* mirror = &objects[static_cast<std::size_t>(first)];
      Eigen::Vector3f point = paths.reflectionEcho(k, i, points[i]);
      Eigen::Vector3f apex = sensor_origin;
      const float apex_side = mirror->signedDistance(apex);
      const float point_side = mirror->signedDistance(point);
      Eigen::Vector3f crossing = apex + (apex_side / (apex_side - point_side)) * (point - apex);
      int length = 1;
      bool explained = true;
      while (true)
      {
        const Eigen::Vector3f reflected = mirror->reflect(point);
        const Eigen::Vector3f reflected_apex = mirror->reflect(apex);
        std::int32_t next = ReflectionPaths::kNoPath;
        float nearest = std::numeric_limits<float>::infinity();
        for (const std::int32_t m : mirrors)
        {
          const ReflectiveObject& candidate = objects[static_cast<std::size_t>(m)];
          if (&candidate == mirror || !(candidate.signedDistance(crossing) > threshold))
            continue;
          const ConeHit hit =
              VisionCone(candidate, reflected_apex, threshold, config_.cone_margin).locate(reflected);
          if (hit.relation == ConeRelation::behind && hit.plane_range < nearest)
          {
            nearest = hit.plane_range;
            next = m;
          }
        }
        if (next == ReflectionPaths::kNoPath)
          break;
        if (length == max_reflections)
        {
          explained = false;
          break;
        }
        path = paths.extend(path, next);
        mirror = &objects[static_cast<std::size_t>(next)];
        const float from_side = mirror->signedDistance(reflected_apex);
        const float to_side = mirror->signedDistance(reflected);
        crossing = reflected_apex + (from_side / (from_side - to_side)) * (reflected - reflected_apex);
        apex = reflected_apex;
        point = reflected;
        ++length;
      }
      // A chain of one is the cone labelling's own test; a longer one must not end where the
      // sensor looked through: nothing is there.
      if (explained && length > 1 &&
          evidence.test(mirror->plane, point, mirror->landing_tolerance).outcome == ReflectionOutcome::transmitted)
        explained = false;
      if (!explained)
      {
        labels.echoes[k][i] = Label::error;
        ++counts.unexplained;
        continue;
      }
      paths.setPath(k, i, path);
      counts.multiply_reflected += length > 1 ? 1 : 0;
    }
  }
  return counts;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
