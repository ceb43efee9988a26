#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "object_fixtures.h"

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/shared_normals.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::ObjectType;

constexpr float kDegree = static_cast<float>(M_PI) / 180.0f;

// The sweep holds the surface echoes of the objects added, one beam each (both echoes alike).
struct Wall
{
  core::Sweep sweep;
  std::vector<core::ReflectiveObject> objects;
  std::vector<Eigen::Vector3f> points;

  // An object whose surface echoes are a grid of `across` x `up` points over y in [y0, y1], z in
  // [-0.5, 0.5], at x = surface(y, z) (a millimetre of alternating noise added), its plane
  // `plane` (as its detection gave it) and its rectangle over the same extent.
  void add(float y0, float y1, std::size_t across, std::size_t up, const std::function<float(float, float)>& surface,
           const Eigen::Vector4f& plane)
  {
    core::ReflectiveObject object = test::wallObject(plane[3], y1 - y0, 1.0f, ObjectType::glass,
                                                     static_cast<std::uint32_t>(objects.size()));
    object.plane = plane;
    object.centre = Eigen::Vector3f(surface(0.5f * (y0 + y1), 0.0f), 0.5f * (y0 + y1), 0.0f);
    object.patch_centre = object.centre;
    for (std::size_t i = 0; i < across; ++i)
      for (std::size_t j = 0; j < up; ++j)
      {
        const float y = y0 + (y1 - y0) * static_cast<float>(i) / static_cast<float>(across - 1);
        const float z = -0.5f + static_cast<float>(j) / static_cast<float>(up - 1);
        const float noise = ((i + j) % 2 == 0 ? 1.0f : -1.0f) * 0.001f;
        object.surface_inliers.push_back(core::PointRef{ static_cast<std::uint32_t>(points.size()), 0 });
        points.emplace_back(surface(y, z) + noise, y, z);
      }
    objects.push_back(object);
  }

  void process(const core::SharedNormalConfig& config = core::stageConfigs(core::Params()).shared_normals)
  {
    sweep.resize(1, points.size());
    for (core::EchoCloud& echo : sweep.echoes)
      echo.points = points;
    sweep.computeRanges(Eigen::Vector3f::Zero());
    core::SweepLabels labels;
    labels.reset(sweep.beamCount());
    core::ReflectionEvidence evidence;
    core::SharedNormals(config).process(sweep, core::SweepContext(), evidence, labels, objects);
  }
};

// The plane x = at, facing the sensor at the origin, turned by `tilt` about the vertical.
Eigen::Vector4f wallPlane(float at, float tilt = 0.0f)
{
  return Eigen::Vector4f(-std::cos(tilt), -std::sin(tilt), 0.0f, at);
}

float angleBetween(const Eigen::Vector4f& a, const Eigen::Vector4f& b)
{
  return std::acos(std::min(1.0f, std::fabs(a.head<3>().dot(b.head<3>()))));
}

const auto kWallAt3 = [](float, float) { return 3.0f; };

// The wall x = 3 as the tests see it: a pane of 600 echoes in it, its plane right.
void addLargePane(Wall& wall)
{
  wall.add(0.2f, 1.4f, 30, 20, kWallAt3, wallPlane(3.0f));
}

// Beside it a pane of 40 echoes whose echoes themselves are turned by `degrees` about the
// vertical through y = -0.4 (x grows with y), its plane fitted to them.
void addTurnedSmallPane(Wall& wall, float degrees)
{
  const float slope = std::tan(degrees * kDegree);
  wall.add(-0.6f, -0.2f, 5, 8, [slope](float y, float) { return 3.0f + slope * (y + 0.4f); },
           wallPlane(3.0f, degrees * kDegree));
}

TEST(SharedNormals, ASmallPaneTakesTheNormalOfTheLargerPaneInItsWall)
{
  Wall wall;
  addLargePane(wall);
  // Beside it a pane of 40 echoes in the same wall, detected 1.5 degrees off.
  wall.add(-0.6f, -0.2f, 5, 8, kWallAt3, wallPlane(3.0f, 1.5f * kDegree));
  const Eigen::Vector4f large_before = wall.objects[0].plane;
  wall.process();
  EXPECT_LT(angleBetween(wall.objects[1].plane, wallPlane(3.0f)), 0.05f * kDegree);
  EXPECT_NEAR(wall.objects[1].plane[3], 3.0f, 0.002f);
  // The larger one has no larger sibling: its plane (its own refinement) stays as it was.
  EXPECT_EQ(wall.objects[0].plane, large_before);
  // The small one's rectangle lies on its new plane.
  const core::ReflectiveObject& small = wall.objects[1];
  EXPECT_NEAR(small.signedDistance(small.centre), 0.0f, 1e-5f);
  EXPECT_NEAR(small.width_axis.dot(small.plane.head<3>()), 0.0f, 1e-5f);
  EXPECT_NEAR(small.height_axis.dot(small.plane.head<3>()), 0.0f, 1e-5f);
  EXPECT_NEAR(small.width_axis.norm(), 1.0f, 1e-5f);
  EXPECT_GT(small.height_axis.z(), 0.99f);
}

TEST(SharedNormals, APanelInFrontOfTheWallKeepsItsOwnOffset)
{
  Wall wall;
  addLargePane(wall);
  // A panel 2 cm in front of the wall, parallel to it, its plane detected 1 degree off.
  wall.add(-0.6f, -0.2f, 5, 8, [](float, float) { return 2.98f; }, wallPlane(2.98f, 1.0f * kDegree));
  wall.process();
  EXPECT_LT(angleBetween(wall.objects[1].plane, wallPlane(3.0f)), 0.05f * kDegree);
  EXPECT_NEAR(wall.objects[1].plane[3], 2.98f, 0.002f);
}

TEST(SharedNormals, ThePooledNormalIsWeightedByTheEchoesSoTheLargerPaneLeadsIt)
{
  Wall wall;
  addLargePane(wall);
  // The small pane's echoes themselves turned by 1 degree: fitted alone they would give that
  // tilt, pooled with 600 echoes of the right wall hardly any.
  addTurnedSmallPane(wall, 1.0f);
  wall.process();
  EXPECT_LT(angleBetween(wall.objects[1].plane, wallPlane(3.0f)), 0.1f * kDegree);
}

TEST(SharedNormals, ObjectsInDifferentWallsOrFurtherApartKeepTheirPlanes)
{
  Wall wall;
  addLargePane(wall);
  // 5 degrees off: another wall (a corner window), not one pane detected askew.
  addTurnedSmallPane(wall, 5.0f);
  // 0.3 m in front of the wall: a mirror on a cabinet, not in the wall.
  wall.add(-1.6f, -1.2f, 5, 8, [](float, float) { return 2.7f; }, wallPlane(2.7f, 1.0f * kDegree));
  std::vector<Eigen::Vector4f> before;
  for (const core::ReflectiveObject& object : wall.objects)
    before.push_back(object.plane);
  wall.process();
  for (std::size_t j = 0; j < wall.objects.size(); ++j)
    EXPECT_EQ(wall.objects[j].plane, before[j]) << "object " << j;
}

TEST(SharedNormals, AtAngleZeroTheStageIsOff)
{
  core::Params off;
  off.shared_normal_angle = 0.0;
  EXPECT_FALSE(core::stageConfigs(off).shared_normals.enabled);
  const core::SharedNormalConfig defaults = core::stageConfigs(core::Params()).shared_normals;
  EXPECT_TRUE(defaults.enabled);
  EXPECT_NEAR(std::acos(defaults.min_cosine), 3.0f * kDegree, 1e-4f);

  Wall wall;
  addLargePane(wall);
  wall.add(-0.6f, -0.2f, 5, 8, kWallAt3, wallPlane(3.0f, 1.5f * kDegree));
  const Eigen::Vector4f small_before = wall.objects[1].plane;
  wall.process(core::stageConfigs(off).shared_normals);
  EXPECT_EQ(wall.objects[1].plane, small_before);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
