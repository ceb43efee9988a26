// The neighbours of a beam in the sweep's own sampling (SweepSampling): the beams within a
// window of rows and columns on its grid, and how far a return of a neighbouring beam may lie
// from a return at range R and still be on the same surface: closer than
//   noise_floor + step_factor * R * angle between the two beams.
// On a surface facing the sensor neighbouring returns lie R * angle apart; a step factor of 3
// keeps them neighbours up to 70 degrees of incidence along one grid direction (and along the
// other, further on), and the noise floor covers the range noise of near returns.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct BeamNeighbourhoodConfig
{
  int half_width = 1;          // rows and columns on each side: 1 is the 8 beams around
  double step_factor = 3.0;
  double noise_floor = 0.05;   // [m]
};

class BeamNeighbourhood
{
public:
  BeamNeighbourhood(const SweepSampling& sampling, const BeamNeighbourhoodConfig& config)
    : rows_(sampling.rows)
    , cols_(sampling.cols)
    , wraps_(sampling.wraps)
    , flips_at_seam_(sampling.flips_at_seam)
    , half_width_(config.half_width < 0 ? 0 : static_cast<std::size_t>(config.half_width))
    , noise_floor_(static_cast<float>(config.noise_floor))
  {
    const int w = static_cast<int>(half_width_);
    for (int dr = -w; dr <= w; ++dr)
      for (int dc = -w; dc <= w; ++dc)
      {
        if (dr == 0 && dc == 0)
          continue;
        const double angle = std::hypot(dr * sampling.row_step, dc * sampling.col_step);
        const std::int64_t delta = static_cast<std::int64_t>(dr) * static_cast<std::int64_t>(cols_) + dc;
        offsets_.push_back(Offset{ dr, dc, delta, static_cast<float>(config.step_factor * angle) });
      }
    // Nearest first: a test that needs one neighbour finds it after fewer looks.
    for (std::size_t i = 1; i < offsets_.size(); ++i)
      for (std::size_t j = i; j > 0 && offsets_[j].factor < offsets_[j - 1].factor; --j)
        std::swap(offsets_[j], offsets_[j - 1]);
  }

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }
  std::size_t offsetCount() const { return offsets_.size(); }

  // Calls visit(neighbour beam, offset index) for every beam of the window around (row, col)
  // that lies on the grid, nearest first; stops when visit returns true. Returns whether it did.
  template <typename Visit>
  bool anyNeighbour(std::size_t row, std::size_t col, Visit visit) const
  {
    const std::size_t w = half_width_;
    if (row >= w && row + w < rows_ && col >= w && col + w < cols_)
    {
      // Inside the grid every offset is a constant step in the beam index.
      const std::int64_t beam = static_cast<std::int64_t>(row * cols_ + col);
      for (std::size_t k = 0; k < offsets_.size(); ++k)
        if (visit(static_cast<std::size_t>(beam + offsets_[k].delta), k))
          return true;
      return false;
    }
    for (std::size_t k = 0; k < offsets_.size(); ++k)
    {
      const Offset& o = offsets_[k];
      std::int64_t r = static_cast<std::int64_t>(row) + o.dr;
      std::int64_t c = static_cast<std::int64_t>(col) + o.dc;
      if (r < 0 || r >= static_cast<std::int64_t>(rows_))
      {
        if (!flips_at_seam_ || static_cast<std::size_t>(o.dr < 0 ? -o.dr : o.dr) >= rows_)
          continue;
        // Across the seam of a half rotation: the other end's row, its columns reversed.
        r = r < 0 ? r + static_cast<std::int64_t>(rows_) : r - static_cast<std::int64_t>(rows_);
        c = static_cast<std::int64_t>(cols_) - 1 - c;
      }
      if (c < 0 || c >= static_cast<std::int64_t>(cols_))
      {
        if (!wraps_)
          continue;
        c = (c + static_cast<std::int64_t>(cols_)) % static_cast<std::int64_t>(cols_);
      }
      if (visit(static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c), k))
        return true;
    }
    return false;
  }

  // Squared distance below which a return of the neighbour at offset `k` is on the surface of a
  // return at `range` [m].
  float limitSquared(float range, std::size_t k) const
  {
    const float limit = noise_floor_ + offsets_[k].factor * range;
    return limit * limit;
  }

private:
  struct Offset
  {
    int dr;
    int dc;
    std::int64_t delta;  // dr * cols + dc
    float factor;  // step_factor * the angle between the beams [rad]
  };

  std::size_t rows_;
  std::size_t cols_;
  bool wraps_;
  bool flips_at_seam_;
  std::size_t half_width_;
  float noise_floor_;
  std::vector<Offset> offsets_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
