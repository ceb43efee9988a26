#include "ohm_mirror_detector3d/core/sweep_assembler.h"

#include <cmath>
#include <limits>
#include <utility>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

bool usable(float range, float range_min, float range_max)
{
  return std::isfinite(range) && range >= range_min && range <= range_max;
}
}  // namespace

EchoChoice chooseEchoes(const float* ranges, std::size_t count, float range_min, float range_max)
{
  EchoChoice choice;
  for (std::size_t k = 0; k < count; ++k)
  {
    if (!usable(ranges[k], range_min, range_max))
      continue;
    if (choice.first < 0)
      choice.first = static_cast<int>(k);
    choice.last = static_cast<int>(k);
  }
  return choice;
}

double twistAngle(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& axis)
{
  const Eigen::Vector3d a = axis.normalized();
  return unwrapAngle(2.0 * std::atan2(rotation.vec().dot(a), rotation.w()), 0.0);
}

double unwrapAngle(double angle, double reference)
{
  const double turns = std::round((angle - reference) / (2.0 * kPi));
  return angle - turns * 2.0 * kPi;
}

long SweepBoundary::update(double phase)
{
  if (!started_)
  {
    started_ = true;
    anchor_ = last_ = phase;
    step_ = 0.0;
    return 0;
  }
  if (angular_)
    phase = unwrapAngle(phase, last_);
  step_ = std::abs(phase - last_);
  last_ = phase;
  if (!(period_ > 0.0))
    return 0;
  return static_cast<long>(std::floor((std::abs(phase - anchor_) + 0.5 * step_) / period_));
}

void ProjectedScan::reset(std::size_t beams)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  echo1.assign(beams, Eigen::Vector3f::Constant(nan));
  echo2.assign(beams, Eigen::Vector3f::Constant(nan));
  intensity1.assign(beams, nan);
  intensity2.assign(beams, nan);
}

void SweepAssembler::Buffer::clear()
{
  rows = 0;
  cols = 0;
  for (int e = 0; e < 2; ++e)
  {
    points[e].clear();
    intensities[e].clear();
  }
  has_intensity = true;
  origin_sum.setZero();
  last_stamp_ns = 0;
  index = 0;
}

void SweepAssembler::Buffer::append(const ProjectedScan& scan)
{
  cols = scan.size();
  ++rows;
  points[0].insert(points[0].end(), scan.echo1.begin(), scan.echo1.end());
  points[1].insert(points[1].end(), scan.echo2.begin(), scan.echo2.end());
  intensities[0].insert(intensities[0].end(), scan.intensity1.begin(), scan.intensity1.end());
  intensities[1].insert(intensities[1].end(), scan.intensity2.begin(), scan.intensity2.end());
  has_intensity = has_intensity && scan.has_intensity;
  origin_sum += scan.origin;
  last_stamp_ns = scan.stamp_ns;
}

SweepAssembler::SweepAssembler(double period, bool angular, std::size_t max_rows)
  : boundary_(period, angular), max_rows_(max_rows)
{
}

void SweepAssembler::configure(double period, bool angular)
{
  boundary_.configure(period, angular);
  reset();
}

void SweepAssembler::reset()
{
  boundary_.reset();
  building_.clear();
  complete_.clear();
}

SweepAssembler::AddResult SweepAssembler::add(const ProjectedScan& scan)
{
  AddResult result = AddResult::added;
  if (building_.rows > 0 && scan.size() != building_.cols)
    result = AddResult::width_changed;
  else if (building_.rows >= max_rows_)
    result = AddResult::overflow;
  if (result != AddResult::added)
  {
    building_.clear();
    boundary_.reset();
  }

  const long index = boundary_.update(scan.phase);
  if (building_.rows > 0 && index != building_.index)
  {
    std::swap(complete_, building_);
    building_.clear();
    result = AddResult::sweep_complete;
  }
  if (building_.rows == 0)
    building_.index = index;
  building_.append(scan);
  return result;
}

std::size_t SweepAssembler::takeSweep(Sweep& sweep, SweepContext& context)
{
  const std::size_t rows = complete_.rows;
  if (rows == 0)
    return 0;
  sweep.rows = rows;
  sweep.cols = complete_.cols;
  for (int e = 0; e < 2; ++e)
  {
    EchoCloud& echo = sweep.echoes[static_cast<std::size_t>(e)];
    echo.points.swap(complete_.points[e]);
    echo.intensities.swap(complete_.intensities[e]);
    echo.ranges.resize(echo.points.size());
  }
  sweep.has_intensity = complete_.has_intensity;
  sweep.input_cells.clear();
  const Eigen::Vector3d origin = complete_.origin_sum / static_cast<double>(rows);
  context.stamp_ns = complete_.last_stamp_ns;
  context.sensor_pose = Eigen::Isometry3d::Identity();
  context.sensor_pose.translation() = origin;
  sweep.computeRanges(context.sensorOrigin());
  complete_.clear();
  return rows;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
