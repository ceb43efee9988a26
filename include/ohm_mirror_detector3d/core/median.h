// The median of a sample, for the stages that take one (a step, a reference brightness, a feature).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
// The median of `values` (of an even count the upper middle one), found by partial sorting:
// `values` is reordered. `values` must not be empty; callers say what an empty sample means.
inline float medianInPlace(std::vector<float>& values)
{
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
