#include "ohm_mirror_detector3d/core/mixed_pixels.h"

#include <cmath>

namespace ohm_mirror_detector3d
{
namespace core
{
std::size_t MixedPixels::release(const Sweep& sweep, const SweepSampling& sampling,
                                 const std::vector<ReflectiveObject>& objects, SweepLabels& labels)
{
  const std::size_t beams = sweep.beamCount();
  if (!sampling.hasGrid() || sampling.rows * sampling.cols != beams)
    return 0;
  on_object_.assign(beams, 0);
  for (const ReflectiveObject& object : objects)
    for (const PointRef& ref : object.surface_inliers)
      on_object_[ref.beam] = 1;

  const BeamNeighbourhood neighbourhood(sampling, config_.neighbourhood);
  const float one_surface = static_cast<float>(config_.neighbourhood.noise_floor);
  const std::vector<Label>& labels1 = labels.echoes[0];
  const std::vector<Label>& labels2 = labels.echoes[1];
  auto usable = [&](std::size_t beam, int echo) {
    return labels.echoes[echo][beam] != Label::nanPoint && sweep.echoes[echo].points[beam].allFinite();
  };
  // A beam that returns from one surface: a single return, or two echoes within the noise floor.
  auto oneSurface = [&](std::size_t beam) {
    if (labels1[beam] == Label::errorSurface || labels1[beam] == Label::error ||
        labels2[beam] == Label::errorSurface || labels2[beam] == Label::error)
      return false;
    if (!usable(beam, 0) || !usable(beam, 1))
      return usable(beam, 0) || usable(beam, 1);
    return std::fabs(sweep.echoes[0].ranges[beam] - sweep.echoes[1].ranges[beam]) <= one_surface;
  };

  released_.clear();
  const std::size_t cols = sampling.cols;
  for (std::size_t b = 0; b < beams; ++b)
  {
    int near_echo = -1;
    if (labels1[b] == Label::errorSurface && labels2[b] == Label::error)
      near_echo = 0;
    else if (labels2[b] == Label::errorSurface && labels1[b] == Label::error)
      near_echo = 1;
    if (near_echo < 0 || on_object_[b])
      continue;
    const int far_echo = 1 - near_echo;
    const Eigen::Vector3f& near_point = sweep.echoes[near_echo].points[b];
    const Eigen::Vector3f& far_point = sweep.echoes[far_echo].points[b];
    const float near_range = sweep.echoes[near_echo].ranges[b];
    const float far_range = sweep.echoes[far_echo].ranges[b];
    const std::size_t row = b / cols;
    const std::size_t col = b % cols;
    const bool continues_in_front = neighbourhood.anyNeighbour(row, col, [&](std::size_t other, std::size_t k) {
      if (!oneSurface(other))
        return false;
      const float limit = neighbourhood.limitSquared(near_range, k);
      for (int e = 0; e < 2; ++e)
        if (usable(other, e) && (sweep.echoes[e].points[other] - near_point).squaredNorm() <= limit)
          return true;
      return false;
    });
    if (!continues_in_front)
      continue;
    const bool continues_behind = neighbourhood.anyNeighbour(row, col, [&](std::size_t other, std::size_t k) {
      const float limit = neighbourhood.limitSquared(far_range, k);
      for (int e = 0; e < 2; ++e)
        if (usable(other, e) && (sweep.echoes[e].points[other] - far_point).squaredNorm() <= limit)
          return true;
      return false;
    });
    if (continues_behind)
      released_.push_back(static_cast<std::uint32_t>(b));
  }
  for (const std::uint32_t b : released_)
  {
    labels.echoes[0][b] = Label::unchecked;
    labels.echoes[1][b] = Label::unchecked;
  }
  return released_.size();
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
