#include "ohm_mirror_detector3d/core/glass_growth.h"

namespace ohm_mirror_detector3d
{
namespace core
{
GlassGrowth::GlassGrowth(const ObjectGrowthConfig& config) : config_(config)
{
}

void GlassGrowth::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                          SweepLabels& labels, std::vector<ReflectiveObject>& objects)
{
  const Eigen::Vector3f origin = context.sensorOrigin();
  for (ReflectiveObject& object : objects)
  {
    if (object.type != ObjectType::glass)
      continue;
    crossings_.build(sweep, labels, origin, evidence.angularStep(), object, config_);
    // Whatever the points seen through the pane are (real, or reflections in it), the rays
    // crossed the plane there without a return on it.
    applyGrownExtent(crossings_.grow([](const std::vector<PointRef>&) { return true; }), object);
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
