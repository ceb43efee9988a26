// One sweep of a multi-echo scanner: a grid of beams with two index-aligned echoes.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/labels.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// One echo of every beam, structure of arrays so that a stage touching only
// ranges does not drag positions through the cache.
struct EchoCloud
{
  std::vector<Eigen::Vector3f> points;  // in the sweep frame; non-finite when there is no return
  std::vector<float> ranges;            // distance from the sensor origin, NaN when no return
  std::vector<float> intensities;       // NaN when the input had none

  std::size_t size() const { return points.size(); }
};

// Beams on a grid of rows x cols, beam index = row * cols + col (row-major, as an
// organised PointCloud2). Echo k of beam i is echoes[k].points[i]; the two echoes of a
// beam may arrive in either order (the stages sort it out by range).
// One point of a sweep: echo (0 or 1) and beam index.
struct PointRef
{
  // echo value of an input point that has no grid cell (see Sweep::unbinned); its `beam`
  // is then its index in Sweep::unbinned.
  static constexpr std::uint8_t kNoCell = 255;

  std::uint32_t beam;
  std::uint8_t echo;
};

struct Sweep
{
  std::size_t rows = 0;
  std::size_t cols = 0;
  bool has_intensity = false;
  std::array<EchoCloud, 2> echoes;

  // For inputs whose points are not simply echo 1 then echo 2 in beam order (a dual-return
  // cloud), the cell of every input point, in input order, so that outputs can keep the
  // input's order and count. Empty when the input is two index-aligned echo clouds.
  std::vector<PointRef> input_cells;

  // Input points that belong to no grid cell (non-finite, ring or return index out of range,
  // a second point for a cell and return), as they were in the input; input_cells refers
  // to them with echo == PointRef::kNoCell. The pipeline does not see them; outputs that
  // keep the input's order report them as nanPoint. Unused when input_cells is empty.
  EchoCloud unbinned;

  std::size_t beamCount() const { return rows * cols; }

  // Sizes every array for rows x cols beams; keeps capacity, so a reused sweep does not allocate.
  void resize(std::size_t new_rows, std::size_t new_cols);

  // Fills ranges: the distance of every point from `sensor_origin` (NaN for non-finite
  // points). The origin is the translation of the sweep's SweepContext::sensor_pose, which the
  // pipeline takes the vision cones' apex from: whoever sets that pose computes the ranges
  // from it.
  void computeRanges(const Eigen::Vector3f& sensor_origin);
};

// Labels of both echoes, index-aligned with the sweep.
struct SweepLabels
{
  std::array<std::vector<Label>, 2> echoes;

  void reset(std::size_t beam_count, Label value = Label::unchecked);
  std::size_t count(int echo, Label label) const;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
