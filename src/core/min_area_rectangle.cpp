#include "ohm_mirror_detector3d/core/min_area_rectangle.h"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// > 0 when o -> a -> b turns counter-clockwise.
double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

bool lexicographicLess(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
}
}  // namespace

void convexHull(std::vector<Eigen::Vector2d>& points, std::vector<Eigen::Vector2d>& hull)
{
  hull.clear();
  std::sort(points.begin(), points.end(), lexicographicLess);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const std::size_t n = points.size();
  if (n <= 2)
  {
    hull.assign(points.begin(), points.end());
    return;
  }
  hull.resize(2 * n);
  std::size_t k = 0;
  // Lower chain left to right, then upper chain right to left; popping on cross <= 0
  // also drops collinear vertices.
  for (std::size_t i = 0; i < n; ++i)
  {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0)
      --k;
    hull[k++] = points[i];
  }
  const std::size_t lower_size = k + 1;
  for (std::size_t i = n - 1; i-- > 0;)
  {
    while (k >= lower_size && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0)
      --k;
    hull[k++] = points[i];
  }
  // The last vertex repeats the first.
  hull.resize(k - 1);
}

Rectangle2D minAreaRectangle(const std::vector<Eigen::Vector2d>& hull)
{
  Rectangle2D best;
  const std::size_t m = hull.size();
  if (m == 0)
    return best;
  if (m == 1)
  {
    best.centre = hull[0];
    return best;
  }
  if (m == 2)
  {
    const Eigen::Vector2d segment = hull[1] - hull[0];
    best.centre = 0.5 * (hull[0] + hull[1]);
    best.length = segment.norm();
    if (best.length > 0.0)
      best.axis = segment / best.length;
    return best;
  }

  const auto next = [m](std::size_t i) { return i + 1 == m ? 0 : i + 1; };
  double best_area = std::numeric_limits<double>::infinity();
  // Calipers: vertex farthest along the edge (right), farthest from it (top), farthest
  // against it (left). Each advances at most once around the hull over all edges; the
  // step bound only guards against rounding.
  std::size_t right = 1;
  std::size_t top = 1;
  std::size_t left = 1;
  for (std::size_t i = 0; i < m; ++i)
  {
    const Eigen::Vector2d& base = hull[i];
    const Eigen::Vector2d edge = hull[next(i)] - base;
    const double edge_length = edge.norm();
    if (!(edge_length > 0.0))
      continue;
    const Eigen::Vector2d e = edge / edge_length;
    const Eigen::Vector2d up(-e.y(), e.x());  // into the hull (counter-clockwise order)

    const auto along = [&](std::size_t j) { return (hull[j] - base).dot(e); };
    const auto across = [&](std::size_t j) { return (hull[j] - base).dot(up); };
    if (i == 0)
    {
      right = 1;
      for (std::size_t s = 0; s < m && along(next(right)) > along(right); ++s)
        right = next(right);
      top = right;
      for (std::size_t s = 0; s < m && across(next(top)) > across(top); ++s)
        top = next(top);
      left = top;
      for (std::size_t s = 0; s < m && along(next(left)) < along(left); ++s)
        left = next(left);
    }
    else
    {
      for (std::size_t s = 0; s < m && along(next(right)) > along(right); ++s)
        right = next(right);
      if (top == right || across(right) > across(top))
        top = right;
      for (std::size_t s = 0; s < m && across(next(top)) > across(top); ++s)
        top = next(top);
      if (left == top || along(top) < along(left))
        left = top;
      for (std::size_t s = 0; s < m && along(next(left)) < along(left); ++s)
        left = next(left);
    }

    const double max_along = along(right);
    const double min_along = along(left);
    const double height = across(top);
    const double area = (max_along - min_along) * height;
    if (area < best_area)
    {
      best_area = area;
      best.axis = e;
      best.length = max_along - min_along;
      best.breadth = height;
      best.centre = base + 0.5 * (max_along + min_along) * e + 0.5 * height * up;
    }
  }
  return best;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
