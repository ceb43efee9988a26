#include "ohm_mirror_detector3d/core/echo_comparison.h"

#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
EchoComparison::EchoComparison(const EchoComparisonConfig& config) : threshold_(static_cast<float>(config.threshold))
{
}

std::size_t EchoComparison::apply(const Sweep& sweep, SweepLabels& labels) const
{
  const float threshold = threshold_;
  const std::vector<float>& range1 = sweep.echoes[0].ranges;
  const std::vector<float>& range2 = sweep.echoes[1].ranges;
  std::vector<Label>& label1 = labels.echoes[0];
  std::vector<Label>& label2 = labels.echoes[1];
  std::size_t affected = 0;
  for (std::size_t i = 0; i < range1.size(); ++i)
  {
    if (label1[i] != Label::unchecked || label2[i] != Label::unchecked)
      continue;
    if (!(std::fabs(range1[i] - range2[i]) > threshold))
      continue;
    const bool first_is_nearer = range1[i] < range2[i];
    (first_is_nearer ? label1[i] : label2[i]) = Label::errorSurface;
    (first_is_nearer ? label2[i] : label1[i]) = Label::error;
    ++affected;
  }
  return affected;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
