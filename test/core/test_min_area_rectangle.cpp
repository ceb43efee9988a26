#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "ohm_mirror_detector3d/core/min_area_rectangle.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::convexHull;
using core::minAreaRectangle;
using core::Rectangle2D;
using Eigen::Vector2d;

const double kPi = 3.14159265358979323846;

Rectangle2D rectangleOf(std::vector<Vector2d> points)
{
  std::vector<Vector2d> hull;
  convexHull(points, hull);
  return minAreaRectangle(hull);
}

// The smallest area over rectangles with a side on a hull edge, the slow way.
double bruteForceArea(const std::vector<Vector2d>& hull)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i)
  {
    const Vector2d e = (hull[(i + 1) % hull.size()] - hull[i]).normalized();
    const Vector2d up(-e.y(), e.x());
    double min_a = 1e300, max_a = -1e300, min_b = 1e300, max_b = -1e300;
    for (const Vector2d& p : hull)
    {
      min_a = std::min(min_a, p.dot(e));
      max_a = std::max(max_a, p.dot(e));
      min_b = std::min(min_b, p.dot(up));
      max_b = std::max(max_b, p.dot(up));
    }
    best = std::min(best, (max_a - min_a) * (max_b - min_b));
  }
  return best;
}

TEST(ConvexHull, IsCounterClockwiseWithoutInteriorDuplicateOrCollinearPoints)
{
  std::vector<Vector2d> points = { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 2, 2 }, { 0, 2 },
                                   { 1, 1 }, { 0, 0 }, { 0.5, 1.5 }, { 0, 1 } };
  std::vector<Vector2d> hull;
  convexHull(points, hull);
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_EQ(hull[0], Vector2d(0, 0));
  EXPECT_EQ(hull[1], Vector2d(2, 0));
  EXPECT_EQ(hull[2], Vector2d(2, 2));
  EXPECT_EQ(hull[3], Vector2d(0, 2));
}

TEST(ConvexHull, DegenerateInputs)
{
  std::vector<Vector2d> hull;
  std::vector<Vector2d> none;
  convexHull(none, hull);
  EXPECT_TRUE(hull.empty());

  std::vector<Vector2d> same = { { 1, 2 }, { 1, 2 }, { 1, 2 } };
  convexHull(same, hull);
  ASSERT_EQ(hull.size(), 1u);

  std::vector<Vector2d> line = { { 0, 0 }, { 3, 3 }, { 1, 1 }, { 2, 2 } };
  convexHull(line, hull);
  ASSERT_EQ(hull.size(), 2u);
  EXPECT_EQ(hull[0], Vector2d(0, 0));
  EXPECT_EQ(hull[1], Vector2d(3, 3));
}

TEST(MinAreaRectangle, AxisAlignedRectangle)
{
  const Rectangle2D r = rectangleOf({ { 0, 0 }, { 6, 0 }, { 6, 4 }, { 0, 4 }, { 3, 2 } });
  EXPECT_NEAR(r.area(), 24.0, 1e-12);
  EXPECT_NEAR(std::max(r.length, r.breadth), 6.0, 1e-12);
  EXPECT_NEAR(std::min(r.length, r.breadth), 4.0, 1e-12);
  EXPECT_NEAR(r.centre.x(), 3.0, 1e-12);
  EXPECT_NEAR(r.centre.y(), 2.0, 1e-12);
}

TEST(MinAreaRectangle, DoesNotDependOnOrientation)
{
  for (double degrees = 0.0; degrees < 180.0; degrees += 7.5)
  {
    const double a = degrees * kPi / 180.0;
    const Vector2d ex(std::cos(a), std::sin(a));
    const Vector2d ey(-std::sin(a), std::cos(a));
    const Vector2d centre(1.5, -0.25);
    std::vector<Vector2d> points;
    for (int i = 0; i <= 30; ++i)
      for (int j = 0; j <= 20; ++j)
        points.push_back(centre + (-0.3 + 0.02 * i) * ex + (-0.2 + 0.02 * j) * ey);
    const Rectangle2D r = rectangleOf(points);
    const double long_side = std::max(r.length, r.breadth);
    const double short_side = std::min(r.length, r.breadth);
    EXPECT_NEAR(long_side, 0.6, 1e-9) << degrees << " deg";
    EXPECT_NEAR(short_side, 0.4, 1e-9) << degrees << " deg";
    EXPECT_NEAR((r.centre - centre).norm(), 0.0, 1e-9) << degrees << " deg";
    // The long side lies along ex.
    const Vector2d long_axis = r.length >= r.breadth ? r.axis : r.perpendicular();
    EXPECT_NEAR(std::fabs(long_axis.dot(ex)), 1.0, 1e-9) << degrees << " deg";
  }
}

TEST(MinAreaRectangle, EnclosesEveryPointAndMatchesBruteForceOnRandomSets)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<Vector2d> points;
    const int n = 3 + trial % 40;
    const double stretch = 1.0 + 4.0 * (trial % 5);
    for (int i = 0; i < n; ++i)
      points.push_back(trial % 2 ? Vector2d(stretch * gauss(rng), gauss(rng)) :
                                   Vector2d(stretch * uniform(rng), uniform(rng)));
    const std::vector<Vector2d> original = points;
    std::vector<Vector2d> hull;
    convexHull(points, hull);
    const Rectangle2D r = minAreaRectangle(hull);
    EXPECT_NEAR(r.area(), bruteForceArea(hull), 1e-9 * (1.0 + r.area())) << "trial " << trial;
    EXPECT_NEAR(r.axis.norm(), 1.0, 1e-12);
    for (const Vector2d& p : original)
    {
      const Vector2d d = p - r.centre;
      EXPECT_LE(std::fabs(d.dot(r.axis)), 0.5 * r.length + 1e-9);
      EXPECT_LE(std::fabs(d.dot(r.perpendicular())), 0.5 * r.breadth + 1e-9);
    }
  }
}

TEST(MinAreaRectangle, DegenerateHulls)
{
  const Rectangle2D empty = minAreaRectangle({});
  EXPECT_EQ(empty.area(), 0.0);

  const Rectangle2D point = rectangleOf({ { 1, 2 } });
  EXPECT_EQ(point.centre, Vector2d(1, 2));
  EXPECT_EQ(point.length, 0.0);
  EXPECT_EQ(point.breadth, 0.0);

  const Rectangle2D segment = rectangleOf({ { 0, 0 }, { 3, 4 }, { 1.5, 2 } });
  EXPECT_NEAR(segment.length, 5.0, 1e-12);
  EXPECT_EQ(segment.breadth, 0.0);
  EXPECT_NEAR(segment.centre.x(), 1.5, 1e-12);
  EXPECT_NEAR(segment.centre.y(), 2.0, 1e-12);
  EXPECT_NEAR(std::fabs(segment.axis.dot(Vector2d(0.6, 0.8))), 1.0, 1e-12);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
