#include "ohm_mirror_detector3d/core/range_gate.h"

namespace ohm_mirror_detector3d
{
namespace core
{
RangeGate::RangeGate(const RangeGateConfig& config)
  : min_range_(static_cast<float>(config.min_range)), max_range_(static_cast<float>(config.max_range))
{
}

std::size_t RangeGate::apply(const Sweep& sweep, SweepLabels& labels) const
{
  const float min_range = min_range_;
  const float max_range = max_range_;
  std::size_t gated = 0;
  for (std::size_t k = 0; k < 2; ++k)
  {
    const std::vector<float>& ranges = sweep.echoes[k].ranges;
    std::vector<Label>& echo_labels = labels.echoes[k];
    for (std::size_t i = 0; i < ranges.size(); ++i)
    {
      // Written so that NaN fails the comparison and lands in the gated branch.
      const bool in_range = ranges[i] >= min_range && ranges[i] <= max_range;
      if (!in_range && echo_labels[i] != Label::nanPoint)
      {
        echo_labels[i] = Label::nanPoint;
        ++gated;
      }
    }
  }
  return gated;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
