#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "ohm_mirror_detector3d/core/object_extraction.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using core::ObjectType;
using core::ReflectiveObject;
using Eigen::Vector3f;

const float kPi = 3.14159265358979f;
const float kCm = 0.01f;

// A rectangle in space: centre, unit axes, full extents.
struct Rect
{
  Vector3f centre;
  Vector3f width_axis;
  Vector3f height_axis;
  float width;
  float height;
};

// Samples on a lattice of `spacing` over the rectangle, the first sample `offset` in from
// the low edges (so the samples never touch the edges, as a scanner's rarely do).
std::vector<Vector3f> lattice(const Rect& r, float spacing, float offset = 0.7f * kCm)
{
  std::vector<Vector3f> points;
  for (float a = offset; a <= r.width + 1e-6f; a += spacing)
    for (float b = offset; b <= r.height + 1e-6f; b += spacing)
      points.push_back(r.centre + (a - 0.5f * r.width) * r.width_axis + (b - 0.5f * r.height) * r.height_axis);
  return points;
}

// A rectangle turned by `degrees` about its normal (counter-clockwise seen from the normal).
Rect rotatedInPlane(Rect r, float degrees)
{
  const float a = degrees * kPi / 180.0f;
  const Vector3f w = std::cos(a) * r.width_axis + std::sin(a) * r.height_axis;
  const Vector3f h = -std::sin(a) * r.width_axis + std::cos(a) * r.height_axis;
  r.width_axis = w;
  r.height_axis = h;
  return r;
}

// A mirror at 2 m ahead of the sensor facing it, 60 x 40 cm: width to the sensor's right
// (-y), height up.
Rect wallMirror()
{
  return Rect{ Vector3f(2.0f, 0.1f, 0.2f), -Vector3f::UnitY(), Vector3f::UnitZ(), 0.6f, 0.4f };
}

// Builds a 1 x N sweep and its labels: each surface point is the near echo of a beam
// (errorSurface), its far echo 1.5 m further along the beam (error); each valid point is a
// single return repeated in both echoes. `surface_in_echo2` swaps the order of the echoes.
struct Scene
{
  std::vector<Vector3f> surface;
  std::vector<Vector3f> valid;
  bool surface_in_echo2 = false;

  void add(const std::vector<Vector3f>& points) { surface.insert(surface.end(), points.begin(), points.end()); }

  core::Sweep sweep() const
  {
    std::vector<test::Beam> beams;
    for (const Vector3f& p : surface)
    {
      const Vector3f phantom = p + 1.5f * p.normalized();
      beams.push_back(surface_in_echo2 ? test::Beam{ phantom, p } : test::Beam{ p, phantom });
    }
    for (const Vector3f& p : valid)
      beams.push_back(test::Beam{ p, p });
    return test::makeSweep(beams);
  }

  core::SweepLabels labels() const
  {
    core::SweepLabels labels;
    labels.reset(surface.size() + valid.size(), Label::valid);
    const int near = surface_in_echo2 ? 1 : 0;
    for (std::size_t i = 0; i < surface.size(); ++i)
    {
      labels.echoes[near][i] = Label::errorSurface;
      labels.echoes[1 - near][i] = Label::error;
    }
    return labels;
  }
};

// These scenes are metric lattices with no scan order: the tests pin the original's metric
// parameters (r = 0.1 m, n_object = 100), set explicitly, which the extraction honours.
core::Params metricParams()
{
  core::Params params;
  params.outlier_radius = 0.1;
  params.outlier_min_neighbors = 50;
  params.min_object_points = 100;
  return params;
}

// The lattices of these tests are thin beams (a point where the lattice is, none beside it):
// the rectangle is grown by the whole spacing unless a test gives its beams a footprint.
core::ObjectExtractionConfig latticeConfig(const core::Params& params, double footprint_steps = 0.0)
{
  core::ObjectExtractionConfig config = core::stageConfigs(params).object_extraction;
  config.footprint_steps = footprint_steps;
  return config;
}

std::vector<ReflectiveObject> extract(const Scene& scene, const core::Params& params = metricParams(),
                                      double footprint_steps = 0.0)
{
  core::ObjectExtractor extractor(latticeConfig(params, footprint_steps));
  std::vector<ReflectiveObject> objects;
  extractor.extract(scene.sweep(), Vector3f::Zero(), scene.labels(), objects);
  return objects;
}

::testing::AssertionResult near(const Vector3f& actual, const Vector3f& expected, float tolerance)
{
  if ((actual - expected).norm() <= tolerance)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << actual.transpose() << ") is " << (actual - expected).norm()
                                       << " from (" << expected.transpose() << "), tolerance " << tolerance;
}

// The object is `expected`: plane (normal towards the origin at 0), centre, size, axes and
// corners within `tolerance` [m], normal and axes within `axis_tolerance`.
void expectRect(const ReflectiveObject& o, const Rect& expected, float tolerance, float axis_tolerance = 0.01f)
{
  const Vector3f normal = o.plane.head<3>();
  EXPECT_NEAR(normal.norm(), 1.0f, 1e-5f);
  EXPECT_GT(o.signedDistance(Vector3f::Zero()), 0.0f) << "normal must point towards the sensor";
  EXPECT_TRUE(near(normal, expected.width_axis.cross(expected.height_axis), axis_tolerance));
  EXPECT_NEAR(o.signedDistance(expected.centre), 0.0f, tolerance);
  EXPECT_TRUE(near(o.centre, expected.centre, tolerance));
  EXPECT_NEAR(o.width, expected.width, tolerance);
  EXPECT_NEAR(o.height, expected.height, tolerance);
  EXPECT_TRUE(near(o.width_axis, expected.width_axis, axis_tolerance));
  EXPECT_TRUE(near(o.height_axis, expected.height_axis, axis_tolerance));
  EXPECT_TRUE(near(o.width_axis.cross(o.height_axis), normal, 1e-4f)) << "axes right-handed with the normal";
  const ReflectiveObject truth = [&] {
    ReflectiveObject t;
    t.centre = expected.centre;
    t.width_axis = expected.width_axis;
    t.height_axis = expected.height_axis;
    t.width = expected.width;
    t.height = expected.height;
    return t;
  }();
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_TRUE(near(o.corners()[k], truth.corners()[k], 1.5f * tolerance)) << "corner " << k;
}

TEST(ObjectExtraction, VerticalMirrorGivesOneObjectWithItsPlaneAndRectangle)
{
  Scene scene;
  scene.add(lattice(wallMirror(), 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  const ReflectiveObject& o = objects[0];
  EXPECT_EQ(o.id, 0u);
  EXPECT_EQ(o.type, ObjectType::unknown);
  expectRect(o, wallMirror(), 1.0f * kCm);
  // Plane x = 2 with the normal towards the sensor: -x + 2 = 0.
  EXPECT_NEAR(o.plane[0], -1.0f, 1e-4f);
  EXPECT_NEAR(o.plane[3], 2.0f, 1e-4f);
  ASSERT_EQ(o.surface_inliers.size(), scene.surface.size());
  for (std::size_t i = 0; i < o.surface_inliers.size(); ++i)
  {
    EXPECT_EQ(o.surface_inliers[i].beam, i);
    EXPECT_EQ(o.surface_inliers[i].echo, 0u);
  }
  std::printf("[   SIZE   ] vertical 60 x 40 on a 2 cm lattice: %.2f x %.2f cm\n", 100 * o.width, 100 * o.height);
}

TEST(ObjectExtraction, SamplingBiasIsCorrectedForAnyOffsetOfTheLattice)
{
  // The hull of the samples is about one spacing short; the extractor grows it back.
  for (float offset : { 0.1f * kCm, 0.7f * kCm, 1.3f * kCm, 1.9f * kCm })
  {
    Scene scene;
    scene.add(lattice(wallMirror(), 2.0f * kCm, offset));
    const std::vector<ReflectiveObject> objects = extract(scene);
    ASSERT_EQ(objects.size(), 1u);
    EXPECT_NEAR(objects[0].width, 0.6f, 1.0f * kCm) << "offset " << offset;
    EXPECT_NEAR(objects[0].height, 0.4f, 1.0f * kCm) << "offset " << offset;
  }
  for (float spacing : { 1.0f * kCm, 1.5f * kCm, 2.5f * kCm })
  {
    Scene scene;
    scene.add(lattice(wallMirror(), spacing, 0.4f * spacing));
    const std::vector<ReflectiveObject> objects = extract(scene);
    ASSERT_EQ(objects.size(), 1u);
    // When the extent is not a multiple of the spacing the lattice misses up to one spacing.
    EXPECT_NEAR(objects[0].width, 0.6f, 0.5f * spacing + 1e-3f) << "spacing " << spacing;
    EXPECT_NEAR(objects[0].height, 0.4f, 0.5f * spacing + 1e-3f) << "spacing " << spacing;
    std::printf("[   SIZE   ] vertical 60 x 40 on a %.1f cm lattice: %.2f x %.2f cm\n", 100 * spacing,
                100 * objects[0].width, 100 * objects[0].height);
  }
}

TEST(ObjectExtraction, RectangleRotatedInItsPlaneKeepsItsSize)
{
  // Turned by 30 deg the 60 cm side is still the more horizontal one: min-area, not axis-aligned.
  const Rect rotated = rotatedInPlane(wallMirror(), 30.0f);
  Scene scene;
  scene.add(lattice(rotated, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], rotated, 1.0f * kCm);
  std::printf("[   SIZE   ] rotated 30 deg: %.2f x %.2f cm\n", 100 * objects[0].width, 100 * objects[0].height);
}

TEST(ObjectExtraction, RectangleRotatedPastFortyFiveDegreesSwapsWidthAndHeight)
{
  // Turned by 70 deg the 40 cm side is the more horizontal one, so it is the width.
  const Rect rotated = rotatedInPlane(wallMirror(), 70.0f);
  Scene scene;
  scene.add(lattice(rotated, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  // Width along the old height axis (sign: height axis up, width x height = normal).
  const Rect expected{ rotated.centre, -rotated.height_axis, rotated.width_axis, 0.4f, 0.6f };
  expectRect(objects[0], expected, 1.0f * kCm);
}

TEST(ObjectExtraction, FloorMirrorTakesTheLongerSideAsWidth)
{
  // Lying on the floor 0.6 m below the sensor, 60 cm side across the line of sight.
  // Height axis away from the sensor (+x); width x height = normal (+z, up to the sensor).
  const Rect floor{ Vector3f(1.5f, 0.2f, -0.6f), -Vector3f::UnitY(), Vector3f::UnitX(), 0.6f, 0.4f };
  Scene scene;
  scene.add(lattice(floor, 2.0f * kCm));
  std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], floor, 1.0f * kCm);
  std::printf("[   SIZE   ] floor: %.2f x %.2f cm\n", 100 * objects[0].width, 100 * objects[0].height);

  // 60 cm side along the line of sight: still the width.
  const Rect along{ Vector3f(1.5f, 0.2f, -0.6f), Vector3f::UnitX(), Vector3f::UnitY(), 0.6f, 0.4f };
  Scene scene2;
  scene2.add(lattice(rotatedInPlane(along, 0.0f), 2.0f * kCm));
  objects = extract(scene2);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_NEAR(objects[0].width, 0.6f, 1.0f * kCm);
  EXPECT_NEAR(objects[0].height, 0.4f, 1.0f * kCm);
  EXPECT_NEAR(std::fabs(objects[0].width_axis.x()), 1.0f, 0.01f);
}

TEST(ObjectExtraction, TiltedMirrorHangingAboveTheSensor)
{
  // Tilted 45 deg about a horizontal axis (y), above and ahead of the sensor, facing down
  // towards it; width horizontal (to the sensor's right), height up the slope.
  const Vector3f up_slope = Vector3f(-1.0f, 0.0f, 1.0f).normalized();
  const Rect tilted{ Vector3f(1.2f, -0.1f, 1.0f), -Vector3f::UnitY(), up_slope, 0.6f, 0.4f };
  Scene scene;
  scene.add(lattice(tilted, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], tilted, 1.0f * kCm);
  EXPECT_TRUE(near(objects[0].plane.head<3>(), Vector3f(-1.0f, 0.0f, -1.0f).normalized(), 1e-3f));
  std::printf("[   SIZE   ] tilted 45 deg: %.2f x %.2f cm\n", 100 * objects[0].width, 100 * objects[0].height);
}

TEST(ObjectExtraction, TwoCoplanarPatchesApartAreTwoObjects)
{
  Rect left = wallMirror();
  left.centre = Vector3f(2.0f, 0.8f, 0.0f);
  Rect right = wallMirror();
  right.centre = Vector3f(2.0f, -0.8f, 0.0f);  // 1 m gap between the edges
  Scene scene;
  scene.add(lattice(left, 2.0f * kCm));
  scene.add(lattice(right, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 2u);
  // Ordered by their first point.
  EXPECT_EQ(objects[0].id, 0u);
  EXPECT_EQ(objects[1].id, 1u);
  expectRect(objects[0], left, 1.0f * kCm);
  expectRect(objects[1], right, 1.0f * kCm);
  EXPECT_EQ(objects[0].surface_inliers.size() + objects[1].surface_inliers.size(), scene.surface.size());
}

TEST(ObjectExtraction, PatchesCloserThanTheConnectionDistanceAreOneObject)
{
  // Two halves 5 cm apart (< outlier_radius 0.1 m): one object spanning both.
  Rect a = wallMirror();
  a.width = 0.3f;
  a.centre = Vector3f(2.0f, 0.25f, 0.0f);
  Rect b = a;
  b.centre = Vector3f(2.0f, -0.1f, 0.0f);
  Scene scene;
  scene.add(lattice(a, 2.0f * kCm));
  scene.add(lattice(b, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_NEAR(objects[0].width, 0.65f, 1.0f * kCm);
}

TEST(ObjectExtraction, TwoPlanesAreTwoObjectsLargestFirst)
{
  const Rect wall = wallMirror();
  const Rect floor{ Vector3f(1.0f, -1.0f, -0.6f), -Vector3f::UnitY(), Vector3f::UnitX(), 0.4f, 0.3f };
  Scene scene;
  scene.add(lattice(floor, 2.0f * kCm));
  scene.add(lattice(wall, 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 2u);
  expectRect(objects[0], wall, 1.0f * kCm);  // 600 points: RANSAC's best plane first
  expectRect(objects[1], floor, 1.0f * kCm);
  EXPECT_EQ(objects[1].id, 1u);
}

TEST(ObjectExtraction, APatchWithTooFewPointsIsNoObject)
{
  core::Params params = metricParams();
  Rect small = wallMirror();
  small.width = 0.2f;
  small.height = 0.2f;  // 10 x 10 = 100 points on a 2 cm lattice
  Scene scene;
  scene.add(lattice(small, 2.0f * kCm));
  ASSERT_EQ(scene.surface.size(), 100u);

  params.min_object_points = 101;
  EXPECT_TRUE(extract(scene, params).empty());
  params.min_object_points = 100;  // "at least": exactly n_object points make an object
  EXPECT_EQ(extract(scene, params).size(), 1u);
}

TEST(ObjectExtractionTermination, CoplanarPatchesAllTooSmallGiveNoObjectAndTheLoopEnds)
{
  // Five coplanar patches of 64 points, 1 m apart: the plane has 320 inliers, every patch
  // is below n_object = 100, so all are assigned and nothing is left for another pass.
  Scene scene;
  for (int k = 0; k < 5; ++k)
  {
    Rect patch{ Vector3f(3.0f, -2.4f + 1.2f * static_cast<float>(k), 0.0f), -Vector3f::UnitY(), Vector3f::UnitZ(),
                0.16f, 0.16f };
    scene.add(lattice(patch, 2.0f * kCm));
  }
  ASSERT_EQ(scene.surface.size(), 320u);
  EXPECT_TRUE(extract(scene).empty());
}

TEST(ObjectExtractionTermination, ScatteredPointsWithoutAPlaneGiveNoObject)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  Scene scene;
  for (int i = 0; i < 400; ++i)
    scene.surface.push_back(Vector3f(3.0f + uniform(rng), uniform(rng), uniform(rng)));
  EXPECT_TRUE(extract(scene).empty());
}

TEST(ObjectExtractionTermination, EmptyAndAllValidSweepsGiveNoObject)
{
  EXPECT_TRUE(extract(Scene()).empty());
  Scene valid_only;
  valid_only.valid = lattice(wallMirror(), 2.0f * kCm);
  EXPECT_TRUE(extract(valid_only).empty());
}

TEST(ObjectExtraction, UsesSurfacePointsInEchoTwo)
{
  Scene scene;
  scene.surface_in_echo2 = true;
  scene.add(lattice(wallMirror(), 2.0f * kCm));
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], wallMirror(), 1.0f * kCm);
  ASSERT_EQ(objects[0].surface_inliers.size(), scene.surface.size());
  for (const core::PointRef& ref : objects[0].surface_inliers)
    EXPECT_EQ(ref.echo, 1u);
}

TEST(ObjectExtraction, UsesOnlyErrorSurfacePoints)
{
  // The wall around the mirror (valid points on the same plane) and the phantoms behind
  // it (error) do not enlarge it.
  Scene scene;
  scene.add(lattice(wallMirror(), 2.0f * kCm));
  Rect wall = wallMirror();
  wall.width = 2.0f;
  wall.height = 1.5f;
  for (const Vector3f& p : lattice(wall, 2.0f * kCm))
    if (std::fabs(p.y() - 0.1f) > 0.32f || std::fabs(p.z() - 0.2f) > 0.22f)
      scene.valid.push_back(p);
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], wallMirror(), 1.0f * kCm);
  EXPECT_EQ(objects[0].surface_inliers.size(), 600u);
}

void expectSameObjects(const std::vector<ReflectiveObject>& a, const std::vector<ReflectiveObject>& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    EXPECT_EQ(a[k].id, b[k].id);
    EXPECT_EQ(a[k].plane, b[k].plane);
    EXPECT_EQ(a[k].centre, b[k].centre);
    EXPECT_EQ(a[k].width_axis, b[k].width_axis);
    EXPECT_EQ(a[k].height_axis, b[k].height_axis);
    EXPECT_EQ(a[k].width, b[k].width);
    EXPECT_EQ(a[k].height, b[k].height);
    ASSERT_EQ(a[k].surface_inliers.size(), b[k].surface_inliers.size());
    for (std::size_t i = 0; i < a[k].surface_inliers.size(); ++i)
    {
      EXPECT_EQ(a[k].surface_inliers[i].beam, b[k].surface_inliers[i].beam);
      EXPECT_EQ(a[k].surface_inliers[i].echo, b[k].surface_inliers[i].echo);
    }
  }
}

// Wall mirror, floor mirror and clutter, with range noise.
Scene busyScene(unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.0f * kCm);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  Scene scene;
  scene.add(lattice(wallMirror(), 2.0f * kCm));
  scene.add(lattice(Rect{ Vector3f(1.0f, -1.0f, -0.6f), -Vector3f::UnitY(), Vector3f::UnitX(), 0.4f, 0.3f },
                    2.0f * kCm));
  for (Vector3f& p : scene.surface)
    p += noise(rng) * p.normalized();
  for (int i = 0; i < 150; ++i)
    scene.surface.push_back(Vector3f(4.0f + uniform(rng), 2.0f * uniform(rng), uniform(rng)));
  return scene;
}

TEST(ObjectExtraction, IsDeterministic)
{
  const Scene scene = busyScene(11);
  const core::Sweep sweep = scene.sweep();
  const core::SweepLabels labels = scene.labels();
  const core::ObjectExtractionConfig config = latticeConfig(metricParams());
  core::ObjectExtractor extractor(config);
  std::vector<ReflectiveObject> first, second, fresh;
  extractor.extract(sweep, Vector3f::Zero(), labels, first);
  extractor.extract(sweep, Vector3f::Zero(), labels, second);
  core::ObjectExtractor(config).extract(sweep, Vector3f::Zero(), labels, fresh);
  ASSERT_EQ(first.size(), 2u);
  expectSameObjects(first, second);
  expectSameObjects(first, fresh);
}

TEST(ObjectExtraction, ReusesItsBuffersAcrossSweeps)
{
  const Scene a = busyScene(5);
  Scene b;
  Rect left = wallMirror();
  left.centre = Vector3f(2.0f, 0.8f, 0.0f);
  b.add(lattice(left, 1.0f * kCm));  // larger than a
  Scene c;                            // smaller than both
  c.add(lattice(wallMirror(), 3.0f * kCm));

  core::ObjectExtractor extractor(latticeConfig(metricParams()));
  std::vector<ReflectiveObject> a1, b1, c1, a2;
  extractor.extract(a.sweep(), Vector3f::Zero(), a.labels(), a1);
  extractor.extract(b.sweep(), Vector3f::Zero(), b.labels(), b1);
  extractor.extract(c.sweep(), Vector3f::Zero(), c.labels(), c1);
  a2.resize(7);  // cleared first
  extractor.extract(a.sweep(), Vector3f::Zero(), a.labels(), a2);
  expectSameObjects(a1, a2);
  expectSameObjects(b1, extract(b));
  expectSameObjects(c1, extract(c));
  ASSERT_EQ(b1.size(), 1u);
  ASSERT_EQ(c1.size(), 1u);
  expectRect(b1[0], left, 1.0f * kCm);
  EXPECT_NEAR(c1[0].width, 0.6f, 1.5f * kCm);
}

TEST(ObjectExtraction, RangeNoiseOfOneCentimetreKeepsTheSizeWithinTwo)
{
  // A scanner's noise is along the beam (Hokuyo: +-3 cm); here sigma = 1 cm.
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 1.0f * kCm);
    for (const Rect& r : { wallMirror(), rotatedInPlane(wallMirror(), 30.0f) })
    {
      Scene scene;
      scene.add(lattice(r, 2.0f * kCm));
      for (Vector3f& p : scene.surface)
        p += noise(rng) * p.normalized();
      const std::vector<ReflectiveObject> objects = extract(scene);
      ASSERT_EQ(objects.size(), 1u);
      expectRect(objects[0], r, 2.0f * kCm);
      std::printf("[   SIZE   ] range noise 1 cm, seed %u: %.2f x %.2f cm\n", seed, 100 * objects[0].width,
                  100 * objects[0].height);
    }
  }
}

TEST(ObjectExtraction, RangeNoiseOfThreeCentimetresKeepsTheSizeWithinTwo)
{
  // The Hokuyo's specified +-3 cm as sigma, with d_thres_plane raised to keep the points.
  core::Params params = metricParams();
  params.plane_threshold = 0.12;
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 3.0f * kCm);
    Scene scene;
    scene.add(lattice(wallMirror(), 2.0f * kCm));
    for (Vector3f& p : scene.surface)
      p += noise(rng) * p.normalized();
    const std::vector<ReflectiveObject> objects = extract(scene, params);
    ASSERT_EQ(objects.size(), 1u);
    expectRect(objects[0], wallMirror(), 2.0f * kCm, 0.03f);  // plane tilted by up to ~1.7 deg
    std::printf("[   SIZE   ] range noise 3 cm, seed %u: %.2f x %.2f cm\n", seed, 100 * objects[0].width,
                100 * objects[0].height);
  }
}

TEST(ObjectExtraction, AFrameInFrontOfThePaneTiltsNeitherThePlaneNorTheRectangle)
{
  // A pane's frame returns near echoes too (mixed pixels at its edge): a 10 cm strip along
  // one side, 3 cm in front of the glass, within RANSAC's 5 cm band and connected to the pane.
  // A least-squares plane through both tilts by about a degree and its rectangle takes in the
  // frame; the plane refitted on the points within 3 robust sigma is the pane's.
  std::vector<float> widths;
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 0.5f * kCm);
    const Rect pane = wallMirror();
    Scene scene;
    scene.add(lattice(pane, 2.0f * kCm));
    const Vector3f towards_sensor = -pane.width_axis.cross(pane.height_axis);
    const Rect frame{ pane.centre + (0.5f * pane.width + 5.0f * kCm) * pane.width_axis + 3.0f * kCm * towards_sensor,
                      pane.width_axis, pane.height_axis, 10.0f * kCm, pane.height };
    const std::vector<Vector3f> frame_points = lattice(frame, 2.0f * kCm, 1.0f * kCm);
    scene.add(frame_points);
    for (Vector3f& p : scene.surface)
      p += noise(rng) * p.normalized();
    const std::vector<ReflectiveObject> objects = extract(scene);
    ASSERT_EQ(objects.size(), 1u);
    const ReflectiveObject& o = objects[0];
    const float tilt_deg =
        std::acos(std::min(1.0f, std::fabs(o.plane.head<3>().dot(towards_sensor)))) * 180.0f / kPi;
    EXPECT_LT(tilt_deg, 0.25f) << "seed " << seed;  // least squares through both: 1.8 deg
    EXPECT_NEAR(o.signedDistance(pane.centre), 0.0f, 0.3f * kCm) << "seed " << seed;
    EXPECT_NEAR(o.height, pane.height, 2.0f * kCm) << "seed " << seed;
    widths.push_back(o.width);
    // The frame's points are no surface points of the pane (at most the few its noise puts
    // within the cut).
    EXPECT_LE(o.surface_inliers.size(), scene.surface.size() - frame_points.size() + frame_points.size() / 20)
        << "seed " << seed;
    std::printf("[  FRAME   ] seed %u: tilt %.3f deg, %.2f x %.2f cm, %zu surface points of %zu\n", seed, tilt_deg,
                100 * o.width, 100 * o.height, o.surface_inliers.size(), scene.surface.size());
  }
  // The odd frame point that noise puts within the cut widens the rectangle of some sweeps
  // (it is a point on the hull); the median sweep's rectangle is the pane's (with the frame in
  // it: 70.5 cm).
  std::nth_element(widths.begin(), widths.begin() + 2, widths.end());
  EXPECT_NEAR(widths[2], 0.6f, 3.0f * kCm);
}

TEST(ObjectExtraction, IsotropicNoiseInflatesTheRectangleByItsSpread)
{
  // Noise within the plane (not what a scanner does: its noise is along the beam) moves the
  // outermost points outwards, and the hull follows them: with sigma = 1 cm on a 2 cm lattice
  // the sizes come out 2-4.5 cm large. This pins that limit of a hull-based rectangle.
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 1.0f * kCm);
    Scene scene;
    scene.add(lattice(wallMirror(), 2.0f * kCm));
    for (Vector3f& p : scene.surface)
      p += Vector3f(noise(rng), noise(rng), noise(rng));
    const std::vector<ReflectiveObject> objects = extract(scene);
    ASSERT_EQ(objects.size(), 1u);
    const ReflectiveObject& o = objects[0];
    EXPECT_TRUE(near(o.centre, wallMirror().centre, 1.0f * kCm));
    EXPECT_TRUE(near(o.plane.head<3>(), -Vector3f::UnitX(), 0.01f));
    EXPECT_TRUE(near(o.width_axis, -Vector3f::UnitY(), 0.03f));
    EXPECT_GE(o.width, 0.6f);
    EXPECT_LE(o.width, 0.6f + 4.5f * kCm);
    EXPECT_GE(o.height, 0.4f);
    EXPECT_LE(o.height, 0.4f + 4.5f * kCm);
    std::printf("[   SIZE   ] isotropic noise 1 cm, seed %u: %.2f x %.2f cm\n", seed, 100 * o.width, 100 * o.height);
  }
}

TEST(ObjectExtraction, MirrorSampledByAScannerGrid)
{
  // Beams on a grid of 0.5 deg x 0.7 deg from the origin, hitting the wall mirror at 2 m:
  // spacing about 1.7 cm x 2.5 cm, varying over the mirror.
  const Rect r = wallMirror();
  Scene scene;
  const float deg = kPi / 180.0f;
  for (float elevation = -20.0f * deg; elevation <= 20.0f * deg; elevation += 0.7f * deg)
    for (float azimuth = -20.0f * deg; azimuth <= 20.0f * deg; azimuth += 0.5f * deg)
    {
      const Vector3f dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
      const Vector3f p = dir * (r.centre.x() / dir.x());
      if (std::fabs(p.y() - r.centre.y()) <= 0.5f * r.width && std::fabs(p.z() - r.centre.z()) <= 0.5f * r.height)
        scene.surface.push_back(p);
    }
  const std::vector<ReflectiveObject> objects = extract(scene);
  ASSERT_EQ(objects.size(), 1u);
  expectRect(objects[0], r, 2.0f * kCm);
  std::printf("[   SIZE   ] scanner grid 0.5 x 0.7 deg at 2 m (%zu points): %.2f x %.2f cm\n", scene.surface.size(),
              100 * objects[0].width, 100 * objects[0].height);
}

// Beams on a square grid of `step` from the origin, shifted by `phase` steps, whose footprint
// (full angle `divergence`) returns the wall mirror while any of it is on the mirror, each
// point on the beam's centre: the beams just beside an edge return from beyond the edge.
Scene mirrorSeenWithFootprint(float step, float divergence, float phase)
{
  const Rect r{ Vector3f(2.0f, 0.0f, 0.0f), -Vector3f::UnitY(), Vector3f::UnitZ(), 0.6f, 0.4f };  // straight ahead
  Scene scene;
  const float reach = 0.5f * divergence;
  for (int i = 0; i * step < 0.5f; ++i)
    for (int j = 0; j * step < 0.5f; ++j)
    {
      const float elevation = -0.25f + (static_cast<float>(i) + phase) * step;
      const float azimuth = -0.25f + (static_cast<float>(j) + phase) * step;
      const Vector3f dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
      const Vector3f p = dir * (r.centre.x() / dir.x());
      const float slack = reach * p.norm();
      if (std::fabs(p.y() - r.centre.y()) <= 0.5f * r.width + slack &&
          std::fabs(p.z() - r.centre.z()) <= 0.5f * r.height + slack)
        scene.surface.push_back(p);
    }
  return scene;
}

// Mean width and height [m] over grid phases 0, 1/8, ..., 7/8 of a step (where the samples
// fall relative to the edges decides the hull of one sweep; the mean shows the bias).
Eigen::Vector2f meanSize(float step, float divergence, double footprint_steps)
{
  Eigen::Vector2f sum = Eigen::Vector2f::Zero();
  const int phases = 8;
  for (int k = 0; k < phases; ++k)
  {
    const std::vector<ReflectiveObject> objects =
        extract(mirrorSeenWithFootprint(step, divergence, static_cast<float>(k) / phases), metricParams(),
                footprint_steps);
    EXPECT_EQ(objects.size(), 1u) << "phase " << k;
    if (!objects.empty())
      sum += Eigen::Vector2f(objects[0].width, objects[0].height);
  }
  return sum / static_cast<float>(phases);
}

TEST(ObjectExtraction, BeamFootprintBeyondTheEdgesIsNotGrownTwice)
{
  // A UTM-30LX-EW: 0.25 deg steps, beams of 0.25 deg, at 2 m: 4.4 mm per side beyond the
  // edges, as much as the spacing (8.7 mm) leaves out. The footprint covers the sampling gap.
  const float deg = kPi / 180.0f;
  const Eigen::Vector2f with_footprint = meanSize(0.25f * deg, 0.25f * deg, 1.0);
  // Height to 5 mm: rows of one elevation curve up towards the mirror's sides (z grows as
  // 1 / cos(azimuth)), so the corners' samples reach 2 mm higher and lower than mid-width.
  EXPECT_NEAR(with_footprint.x(), 0.6f, 0.3f * kCm);
  EXPECT_NEAR(with_footprint.y(), 0.4f, 0.5f * kCm);
  // Taken for thin beams, the same points make the rectangle about a footprint too large.
  const Eigen::Vector2f thin = meanSize(0.25f * deg, 0.25f * deg, 0.0);
  EXPECT_GT(thin.x(), 0.6f + 0.6f * kCm);
  EXPECT_GT(thin.y(), 0.4f + 0.6f * kCm);
  std::printf("[   SIZE   ] 0.25 deg beams of 0.25 deg at 2 m, mean over phases: %.2f x %.2f cm (as thin beams "
              "%.2f x %.2f cm)\n",
              100 * with_footprint.x(), 100 * with_footprint.y(), 100 * thin.x(), 100 * thin.y());
}

TEST(ObjectExtraction, SamplingGapWiderThanTheFootprintIsGrownByTheRest)
{
  // 0.5 deg steps with beams of 0.25 deg (footprint_steps 0.5): the hull misses the part of
  // the spacing the footprint does not cover, and gets it back.
  const float deg = kPi / 180.0f;
  const Eigen::Vector2f size = meanSize(0.5f * deg, 0.25f * deg, 0.5);
  EXPECT_NEAR(size.x(), 0.6f, 0.3f * kCm);
  EXPECT_NEAR(size.y(), 0.4f, 0.5f * kCm);  // see above
  std::printf("[   SIZE   ] 0.5 deg beams of 0.25 deg at 2 m, mean over phases: %.2f x %.2f cm\n", 100 * size.x(),
              100 * size.y());
}

// The angle [deg] between the object's normal and `expected` (either sign).
float normalErrorDeg(const ReflectiveObject& o, const Vector3f& expected)
{
  const float c = std::min(1.0f, std::fabs(o.plane.head<3>().normalized().dot(expected.normalized())));
  return std::acos(c) * 180.0f / kPi;
}

// The lattice of `r` at 1 cm, each sample moved along its beam by Gaussian range noise of 1.5 cm.
Scene noisyLattice(const Rect& r, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.5f * kCm);
  Scene scene;
  scene.add(lattice(r, 1.0f * kCm, 0.0f));
  for (Vector3f& p : scene.surface)
    p += noise(rng) * p.normalized();
  return scene;
}

TEST(ObjectExtraction, AStripNoWiderThanTheRangeNoiseFacesTheBeam)
{
  // A pane's specular spot 2.8 m ahead seen by a few scan lines: three columns 1 cm apart, 41
  // rows 1 cm apart, range noise 1.5 cm along the beams. Across the strip the points spread
  // less than along the beams, so the least-squares plane stands edge-on to the sensor (a
  // surface echo at grazing incidence, which glass never returns); the plane through the
  // strip's axis facing the beam is the pane's.
  core::Params params = metricParams();
  params.plane_threshold = 0.12;
  const Rect strip{ Vector3f(2.8f, 0.0f, 0.1f), -Vector3f::UnitY(), Vector3f::UnitZ(), 0.02f, 0.4f };
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    const std::vector<ReflectiveObject> objects = extract(noisyLattice(strip, seed), params);
    ASSERT_EQ(objects.size(), 1u) << "seed " << seed;
    EXPECT_LT(normalErrorDeg(objects[0], Vector3f::UnitX()), 3.0f) << "seed " << seed;
    EXPECT_GT(objects[0].signedDistance(Vector3f::Zero()), 0.0f);
    EXPECT_NEAR(objects[0].signedDistance(strip.centre), 0.0f, 1.0f * kCm);
  }
}

TEST(ObjectExtraction, APatchWideEnoughKeepsItsOwnPlaneAtGrazingIncidence)
{
  // A 30 x 40 cm patch seen at 60 degrees incidence with the same noise: its extent fixes its
  // plane, and the extraction keeps it (a shiny metal panel returns a surface echo at any angle).
  core::Params params = metricParams();
  params.plane_threshold = 0.12;
  const float a = 60.0f * kPi / 180.0f;
  const Vector3f c(2.5f, 0.0f, 0.0f);
  const Vector3f n(-std::cos(a), -std::sin(a), 0.0f);  // the patch's normal, pointing back at 60 deg
  const Rect wide{ c, Vector3f::UnitZ().cross(n).normalized(), Vector3f::UnitZ(), 0.3f, 0.4f };
  const std::vector<ReflectiveObject> objects = extract(noisyLattice(wide, 7), params);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_LT(normalErrorDeg(objects[0], n), 3.0f);
  EXPECT_GT(normalErrorDeg(objects[0], Vector3f::UnitX()), 50.0f);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
