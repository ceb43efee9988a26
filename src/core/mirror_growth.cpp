#include "ohm_mirror_detector3d/core/mirror_growth.h"

namespace ohm_mirror_detector3d
{
namespace core
{
MirrorGrowth::MirrorGrowth(const ObjectGrowthConfig& config) : config_(config)
{
}

void MirrorGrowth::process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
                           SweepLabels& labels, std::vector<ReflectiveObject>& objects)
{
  const Eigen::Vector3f origin = context.sensorOrigin();
  for (ReflectiveObject& object : objects)
  {
    if (object.type != ObjectType::mirror)
      continue;
    crossings_.build(sweep, labels, origin, evidence.angularStep(), object, config_);
    const GrownExtent extent = crossings_.grow([&](const std::vector<PointRef>& points) {
      // An even sample of the cell's points: the ones that land on what the sensor saw against
      // the ones that are real or cannot be told; the test stops once the rest of the sample
      // cannot change the answer.
      const std::size_t stride = points.size() > kTestedPerCell ? points.size() / kTestedPerCell : 1;
      const std::size_t sample = (points.size() + stride - 1) / stride;
      std::size_t phantoms = 0, ambiguous = 0, other = 0;
      for (std::size_t i = 0, tested = 0; i < points.size(); i += stride, ++tested)
      {
        const std::size_t left = sample - tested;
        if (phantoms > 0 && phantoms + ambiguous >= other + left)
          return true;
        if (other > phantoms + ambiguous + left)
          return false;
        const Eigen::Vector3f& p = sweep.echoes[points[i].echo].points[points[i].beam];
        switch (evidence.test(object.plane, p, object.landing_tolerance).outcome)
        {
          case ReflectionOutcome::phantom: ++phantoms; break;
          case ReflectionOutcome::ambiguous: ++ambiguous; break;
          default: ++other; break;
        }
      }
      // A floor seen through a doorway beside a mirror standing in it is ambiguous too: a cell
      // needs a phantom of its own.
      return phantoms > 0 && phantoms + ambiguous >= other;
    });
    applyGrownExtent(extent, object);
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
