#include "ohm_mirror_detector3d/core/cone_labelling.h"

#include <cmath>
#include <limits>

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
}  // namespace

void ObjectAssignment::reset(std::size_t beam_count)
{
  for (std::vector<std::int32_t>& objects : echoes)
    objects.assign(beam_count, kNoObject);
}

void labelByVisionCones(const Sweep& sweep, const Params& params, std::vector<ReflectiveObject>& objects,
                        SweepLabels& labels, ObjectAssignment& assignment)
{
  const std::size_t beams = sweep.beamCount();
  assignment.reset(beams);
  std::vector<double> intensity_sums(objects.size(), 0.0);
  std::vector<std::size_t> intensity_counts(objects.size(), 0);
  for (ReflectiveObject& object : objects)
    object.surface_points = object.behind_points = 0;

  const float plane_threshold = static_cast<float>(params.plane_threshold);
  const float margin = static_cast<float>(params.vision_cone_margin);
  std::vector<VisionCone> cones;
  cones.reserve(objects.size());
  for (const ReflectiveObject& object : objects)
    cones.emplace_back(object, sweep.origin, plane_threshold, margin);
  for (std::size_t k = 0; k < 2; ++k)
  {
    const EchoCloud& echo = sweep.echoes[k];
    for (std::size_t i = 0; i < beams; ++i)
    {
      Label& label = labels.echoes[k][i];
      if (label == Label::nanPoint)
        continue;
      std::int32_t nearest = ObjectAssignment::kNoObject;
      ConeHit nearest_hit;
      nearest_hit.plane_range = std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < objects.size(); ++j)
      {
        const ConeHit hit = cones[j].locate(echo.points[i]);
        const bool affected = hit.relation == ConeRelation::onSurface || hit.relation == ConeRelation::behind;
        if (affected && hit.plane_range < nearest_hit.plane_range)
        {
          nearest = static_cast<std::int32_t>(j);
          nearest_hit = hit;
        }
      }
      if (nearest == ObjectAssignment::kNoObject)
      {
        if (label != Label::error)
          label = Label::valid;
        continue;
      }
      ReflectiveObject& object = objects[static_cast<std::size_t>(nearest)];
      assignment.echoes[k][i] = nearest;
      if (nearest_hit.relation == ConeRelation::onSurface)
      {
        label = surfaceLabel(object.type);
        ++object.surface_points;
        if (std::isfinite(echo.intensities[i]))
        {
          intensity_sums[static_cast<std::size_t>(nearest)] += echo.intensities[i];
          ++intensity_counts[static_cast<std::size_t>(nearest)];
        }
      }
      else
      {
        label = behindLabel(object.type);
        ++object.behind_points;
      }
    }
  }
  for (std::size_t j = 0; j < objects.size(); ++j)
    objects[j].mean_surface_intensity = intensity_counts[j] > 0 ?
                                            static_cast<float>(intensity_sums[j] / intensity_counts[j]) :
                                            std::numeric_limits<float>::quiet_NaN();
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
