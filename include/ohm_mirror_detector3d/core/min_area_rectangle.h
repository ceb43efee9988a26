// 2-D geometry for object extraction: convex hull and minimum-area enclosing rectangle.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace core
{
// A rectangle in the plane: centre, unit axis along its first side, and its full extents
// along that axis and along the axis turned +90 degrees (-axis.y, axis.x).
struct Rectangle2D
{
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();
  double length = 0.0;  // extent along axis
  double breadth = 0.0; // extent along the perpendicular axis

  Eigen::Vector2d perpendicular() const { return Eigen::Vector2d(-axis.y(), axis.x()); }
  double area() const { return length * breadth; }
};

// Convex hull (Andrew's monotone chain) of `points`, counter-clockwise, without repeated
// or collinear vertices. Sorts `points` in place (and drops exact duplicates from it);
// `hull` is overwritten and keeps its capacity. One distinct point gives a hull of one
// vertex, collinear points a hull of the two end points.
void convexHull(std::vector<Eigen::Vector2d>& points, std::vector<Eigen::Vector2d>& hull);

// Minimum-area rectangle enclosing a convex polygon given as a counter-clockwise hull
// (as convexHull makes it), by rotating calipers: one side of the optimum lies on a hull
// edge, and the extreme vertices along and across each edge advance monotonically, so
// all edges are tried in O(hull size). A two-vertex hull gives a rectangle of zero
// breadth along the segment, a one-vertex hull a zero rectangle at that point, an empty
// hull a zero rectangle at the origin.
Rectangle2D minAreaRectangle(const std::vector<Eigen::Vector2d>& hull);

}  // namespace core
}  // namespace ohm_mirror_detector3d
