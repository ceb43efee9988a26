// The extent of an object kept over sweeps: an occupancy grid of square cells on its plane, the
// union of the patches the sweeps saw of it. A union of rectangles seen from different places is
// not a rectangle (an L of two panes, a patch shifted by odometry drift); a grid keeps the union
// itself, bounded in size by the object's area rather than the number of sweeps, and answers
// "does this new patch overlap or touch what is known" with a few lookups per cell.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
class PlaneGrid
{
public:
  // Cell (i, j) covers [i, i + 1) x [j, j + 1) in cell units of the plane's axes.
  bool empty() const { return count_ == 0; }
  std::size_t count() const { return count_; }
  bool occupied(int i, int j) const;
  void set(int i, int j);
  // Sets every cell of `other` (same cell units, same axes).
  void add(const PlaneGrid& other);
  // Whether a cell within `reach` cells (either axis) of (i, j) is occupied.
  bool occupiedNear(int i, int j, int reach) const;

  // Bounding cells of the occupied ones (valid when not empty), inclusive.
  int minI() const { return min_i_; }
  int maxI() const { return max_i_; }
  int minJ() const { return min_j_; }
  int maxJ() const { return max_j_; }

  // Calls `visit(i, j)` for every occupied cell.
  void forEach(const std::function<void(int, int)>& visit) const;

  // The occupied cells as one string per row of j from minJ() up, '1' occupied, '0' free, from
  // column minI() (for the map file).
  std::vector<std::string> rows() const;
  // The inverse: rows as rows() writes them, starting at (i0, j0); false (the grid left empty)
  // when a row holds another character.
  bool setRows(int i0, int j0, const std::vector<std::string>& rows);

private:
  // Grows the storage to hold (i, j), with some margin so that growing sweep by sweep does not
  // copy every time.
  void cover(int i, int j);
  std::size_t index(int i, int j) const
  {
    return static_cast<std::size_t>(j - j0_) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(i - i0_);
  }
  bool inside(int i, int j) const { return i >= i0_ && j >= j0_ && i < i0_ + cols_ && j < j0_ + rows_; }
  void buildIntegral() const;

  int i0_ = 0, j0_ = 0, cols_ = 0, rows_ = 0;
  std::vector<std::uint8_t> cells_;
  std::size_t count_ = 0;
  int min_i_ = 0, max_i_ = -1, min_j_ = 0, max_j_ = -1;
  // Summed-area table of cells_ for occupiedNear, rebuilt when the cells changed since.
  mutable std::vector<std::uint32_t> integral_;
  mutable bool integral_valid_ = false;
};

// The cells whose centres lie inside the convex quadrilateral `corners` (in cell units, in
// order around it); a quadrilateral smaller than a cell that covers no centre gives the cell
// of its centre, so that every patch leaves a trace.
void rasterizeQuad(const std::array<Eigen::Vector2d, 4>& corners, const std::function<void(int, int)>& visit);

}  // namespace core
}  // namespace ohm_mirror_detector3d
