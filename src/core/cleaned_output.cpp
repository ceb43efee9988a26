#include "ohm_mirror_detector3d/core/cleaned_output.h"

namespace ohm_mirror_detector3d
{
namespace core
{
void collectCleaned(const Sweep& sweep, const SweepLabels& labels, const std::vector<ReflectiveObject>& objects,
                    const ReflectionPaths& paths, std::vector<OutputPoint>& cleaned)
{
  cleaned.clear();
  const std::size_t beams = sweep.beamCount();
  for (std::size_t i = 0; i < beams; ++i)
  {
    for (std::size_t k = 0; k < 2; ++k)
    {
      const Label label = labels.echoes[k][i];
      if (!keptInCleaned(label))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      if (k == 1 && p == sweep.echoes[0].points[i] && keptInCleaned(labels.echoes[0][i]))
        continue;
      const Eigen::Vector3f position = label == Label::behindReflective ? paths.backProject(objects, k, i, p) : p;
      cleaned.push_back(OutputPoint{ position, sweep.echoes[k].intensities[i], label,
                                     static_cast<std::uint8_t>(k + 1), static_cast<std::uint32_t>(i) });
    }
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
