#include "ohm_mirror_detector3d/core/sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
void Sweep::resize(std::size_t new_rows, std::size_t new_cols)
{
  rows = new_rows;
  cols = new_cols;
  for (EchoCloud& echo : echoes)
  {
    echo.points.resize(beamCount());
    echo.ranges.resize(beamCount());
    echo.intensities.resize(beamCount());
  }
}

void Sweep::computeRanges(const Eigen::Vector3f& sensor_origin)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (EchoCloud& echo : echoes)
  {
    for (std::size_t i = 0; i < echo.points.size(); ++i)
    {
      const Eigen::Vector3f& p = echo.points[i];
      echo.ranges[i] = p.allFinite() ? (p - sensor_origin).norm() : nan;
    }
  }
}

void SweepLabels::reset(std::size_t beam_count, Label value)
{
  for (std::vector<Label>& labels : echoes)
    labels.assign(beam_count, value);
}

std::size_t SweepLabels::count(int echo, Label label) const
{
  const std::vector<Label>& labels = echoes.at(static_cast<std::size_t>(echo));
  return static_cast<std::size_t>(std::count(labels.begin(), labels.end(), label));
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
