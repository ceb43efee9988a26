#include "ohm_mirror_detector3d/core/plane_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Cells added beyond a new cell when the storage grows.
constexpr int kGrowthMargin = 16;
// A patch covers at most this many cells on a side (at 2.5 cm, 250 m): a larger one is a
// broken pose or plane, not an object, and is not rasterized.
constexpr double kMaxCellsAcross = 10000.0;
}  // namespace

bool PlaneGrid::occupied(int i, int j) const
{
  return inside(i, j) && cells_[index(i, j)] != 0;
}

void PlaneGrid::cover(int i, int j)
{
  if (inside(i, j))
    return;
  const int new_i0 = cols_ == 0 ? i - kGrowthMargin : std::min(i0_, i - kGrowthMargin);
  const int new_j0 = rows_ == 0 ? j - kGrowthMargin : std::min(j0_, j - kGrowthMargin);
  const int new_i1 = cols_ == 0 ? i + kGrowthMargin : std::max(i0_ + cols_, i + kGrowthMargin + 1);
  const int new_j1 = rows_ == 0 ? j + kGrowthMargin : std::max(j0_ + rows_, j + kGrowthMargin + 1);
  const int new_cols = new_i1 - new_i0;
  const int new_rows = new_j1 - new_j0;
  std::vector<std::uint8_t> grown(static_cast<std::size_t>(new_cols) * static_cast<std::size_t>(new_rows), 0);
  for (int y = 0; y < rows_; ++y)
    std::copy_n(cells_.begin() + static_cast<std::ptrdiff_t>(y) * cols_, cols_,
                grown.begin() + static_cast<std::ptrdiff_t>(y + j0_ - new_j0) * new_cols + (i0_ - new_i0));
  cells_.swap(grown);
  i0_ = new_i0;
  j0_ = new_j0;
  cols_ = new_cols;
  rows_ = new_rows;
  integral_valid_ = false;
}

void PlaneGrid::set(int i, int j)
{
  cover(i, j);
  std::uint8_t& cell = cells_[index(i, j)];
  if (cell != 0)
    return;
  cell = 1;
  integral_valid_ = false;
  if (count_ == 0)
  {
    min_i_ = max_i_ = i;
    min_j_ = max_j_ = j;
  }
  else
  {
    min_i_ = std::min(min_i_, i);
    max_i_ = std::max(max_i_, i);
    min_j_ = std::min(min_j_, j);
    max_j_ = std::max(max_j_, j);
  }
  ++count_;
}

void PlaneGrid::add(const PlaneGrid& other)
{
  other.forEach([this](int i, int j) { set(i, j); });
}

void PlaneGrid::forEach(const std::function<void(int, int)>& visit) const
{
  if (count_ == 0)
    return;
  for (int j = min_j_; j <= max_j_; ++j)
    for (int i = min_i_; i <= max_i_; ++i)
      if (cells_[index(i, j)] != 0)
        visit(i, j);
}

void PlaneGrid::buildIntegral() const
{
  const std::size_t stride = static_cast<std::size_t>(cols_) + 1;
  integral_.assign(stride * (static_cast<std::size_t>(rows_) + 1), 0);
  for (int y = 0; y < rows_; ++y)
  {
    std::uint32_t row_sum = 0;
    for (int x = 0; x < cols_; ++x)
    {
      row_sum += cells_[static_cast<std::size_t>(y) * cols_ + x];
      integral_[(y + 1) * stride + x + 1] = integral_[y * stride + x + 1] + row_sum;
    }
  }
  integral_valid_ = true;
}

bool PlaneGrid::occupiedNear(int i, int j, int reach) const
{
  if (count_ == 0 || i + reach < min_i_ || i - reach > max_i_ || j + reach < min_j_ || j - reach > max_j_)
    return false;
  if (!integral_valid_)
    buildIntegral();
  // Clipped to the storage (outside it every cell is free).
  const int x0 = std::max(i - reach, i0_) - i0_;
  const int y0 = std::max(j - reach, j0_) - j0_;
  const int x1 = std::min(i + reach, i0_ + cols_ - 1) - i0_ + 1;
  const int y1 = std::min(j + reach, j0_ + rows_ - 1) - j0_ + 1;
  const std::size_t stride = static_cast<std::size_t>(cols_) + 1;
  const std::uint32_t sum = integral_[y1 * stride + x1] - integral_[y0 * stride + x1] - integral_[y1 * stride + x0] +
                            integral_[y0 * stride + x0];
  return sum > 0;
}

std::vector<std::string> PlaneGrid::rows() const
{
  std::vector<std::string> rows;
  if (count_ == 0)
    return rows;
  for (int j = min_j_; j <= max_j_; ++j)
  {
    std::string row(static_cast<std::size_t>(max_i_ - min_i_ + 1), '0');
    for (int i = min_i_; i <= max_i_; ++i)
      if (cells_[index(i, j)] != 0)
        row[static_cast<std::size_t>(i - min_i_)] = '1';
    rows.push_back(row);
  }
  return rows;
}

bool PlaneGrid::setRows(int i0, int j0, const std::vector<std::string>& rows)
{
  *this = PlaneGrid();
  for (std::size_t y = 0; y < rows.size(); ++y)
    for (std::size_t x = 0; x < rows[y].size(); ++x)
    {
      if (rows[y][x] == '1')
        set(i0 + static_cast<int>(x), j0 + static_cast<int>(y));
      else if (rows[y][x] != '0')
      {
        *this = PlaneGrid();
        return false;
      }
    }
  return true;
}

void rasterizeQuad(const std::array<Eigen::Vector2d, 4>& corners, const std::function<void(int, int)>& visit)
{
  Eigen::Vector2d low = corners[0], high = corners[0];
  for (const Eigen::Vector2d& c : corners)
  {
    if (!c.allFinite())
      return;
    low = low.cwiseMin(c);
    high = high.cwiseMax(c);
  }
  if ((high - low).maxCoeff() > kMaxCellsAcross)
    return;
  // Orientation of the corners, so that "inside" is on the same side of every edge.
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  const double orientation = cross(corners[1] - corners[0], corners[2] - corners[1]) >= 0.0 ? 1.0 : -1.0;
  bool any = false;
  for (int j = static_cast<int>(std::floor(low.y())); j <= static_cast<int>(std::floor(high.y())); ++j)
    for (int i = static_cast<int>(std::floor(low.x())); i <= static_cast<int>(std::floor(high.x())); ++i)
    {
      const Eigen::Vector2d centre(i + 0.5, j + 0.5);
      bool inside = true;
      for (std::size_t k = 0; k < 4 && inside; ++k)
        inside = orientation * cross(corners[(k + 1) % 4] - corners[k], centre - corners[k]) >= 0.0;
      if (inside)
      {
        visit(i, j);
        any = true;
      }
    }
  if (!any)
  {
    const Eigen::Vector2d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
    visit(static_cast<int>(std::floor(centre.x())), static_cast<int>(std::floor(centre.y())));
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
