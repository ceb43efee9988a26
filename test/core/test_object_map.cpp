#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

#include "growth_fixtures.h"
#include "traced_scene.h"

#include "ohm_mirror_detector3d/core/object_map.h"
#include "ohm_mirror_detector3d/core/object_map_file.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/core/plane_grid.h"
#include "ohm_mirror_detector3d/core/post_filter.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::ObjectType;
using test::Panel;
using test::Surface;

// A patch on the plane x = distance (in its sweep's frame) facing the origin: centre (distance,
// y, z), `width` along y, `height` along z.
core::ReflectiveObject patch(float distance, float y, float z, float width, float height, ObjectType type)
{
  core::ReflectiveObject object = test::patchAt(distance, y, z, 1.0f, type);
  object.width = width;
  object.height = height;
  object.surface_inliers.resize(20);
  return object;
}

Eigen::Isometry3d translation(double x, double y, double z)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

core::ObjectMapConfig mapConfig()
{
  core::ObjectMapConfig config;
  config.enabled = true;
  return config;
}

// The map object's bounding rectangle in the fixed frame.
core::ReflectiveObject rectangle(const core::ObjectMap& map, std::size_t k)
{
  return map.toReflectiveObject(map.objects()[k], Eigen::Isometry3d::Identity(), Eigen::Vector3f::Zero());
}

TEST(PlaneGrid, HoldsTheUnionAndAnswersWhatLiesNear)
{
  core::PlaneGrid grid;
  EXPECT_TRUE(grid.empty());
  for (int i = 0; i < 4; ++i)
    grid.set(i, 0);
  grid.set(100, -50);  // far off: the storage grows
  grid.set(2, 0);      // again: counted once
  EXPECT_EQ(grid.count(), 5u);
  EXPECT_TRUE(grid.occupied(100, -50));
  EXPECT_FALSE(grid.occupied(4, 0));
  EXPECT_EQ(grid.minI(), 0);
  EXPECT_EQ(grid.maxI(), 100);
  EXPECT_EQ(grid.minJ(), -50);
  EXPECT_TRUE(grid.occupiedNear(5, 2, 2));  // (3, 0) is 2 cells off both ways
  EXPECT_FALSE(grid.occupiedNear(6, 2, 2));
  EXPECT_FALSE(grid.occupiedNear(5, 2, 1));
  EXPECT_FALSE(grid.occupiedNear(-500, 0, 3));
}

TEST(PlaneGrid, RowsReadBackAndAnythingButZeroAndOneIsRefused)
{
  core::PlaneGrid grid;
  grid.set(-3, 2);
  grid.set(-1, 3);
  grid.set(0, 2);
  const std::vector<std::string> rows = grid.rows();
  ASSERT_EQ(rows, (std::vector<std::string>{ "1001", "0010" }));
  core::PlaneGrid copy;
  ASSERT_TRUE(copy.setRows(grid.minI(), grid.minJ(), rows));
  EXPECT_EQ(copy.count(), 3u);
  EXPECT_TRUE(copy.occupied(-1, 3));
  EXPECT_FALSE(copy.setRows(0, 0, { "10x1" }));
  EXPECT_TRUE(copy.empty());
}

TEST(PlaneGrid, RasterizesTheCellsWhoseCentresLieInsideAndATinyPatchLeavesOne)
{
  std::size_t cells = 0;
  core::rasterizeQuad({ Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 0), Eigen::Vector2d(10, 4), Eigen::Vector2d(0, 4) },
                      [&cells](int, int) { ++cells; });
  EXPECT_EQ(cells, 40u);
  // The same rectangle turned by 45 degrees around its centre: about the same area.
  cells = 0;
  const Eigen::Vector2d c(5, 2);
  const Eigen::Rotation2Dd turn(M_PI / 4);
  core::rasterizeQuad({ c + turn * Eigen::Vector2d(-5, -2), c + turn * Eigen::Vector2d(5, -2),
                        c + turn * Eigen::Vector2d(5, 2), c + turn * Eigen::Vector2d(-5, 2) },
                      [&cells](int, int) { ++cells; });
  EXPECT_NEAR(static_cast<double>(cells), 40.0, 4.0);
  std::vector<std::pair<int, int>> tiny;
  core::rasterizeQuad({ Eigen::Vector2d(3.1, 7.1), Eigen::Vector2d(3.2, 7.1), Eigen::Vector2d(3.2, 7.2),
                        Eigen::Vector2d(3.1, 7.2) },
                      [&tiny](int i, int j) { tiny.emplace_back(i, j); });
  ASSERT_EQ(tiny.size(), 1u);
  EXPECT_EQ(tiny[0], std::make_pair(3, 7));
}

TEST(ObjectMap, PatchesOfOnePlaneSeenFromTwoPlacesMergeUnderOneIdAndTheExtentGrows)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  // A 0.8 x 1.0 m pane at x = 3, y in [-0.4, 0.4], z in [0, 1] of the fixed frame: the first
  // sweep sees its left half, the second (taken 1 m further along y) its right half.
  map.observe({ patch(3.0f, -0.2f, 0.5f, 0.4f, 1.0f, ObjectType::glass) }, Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(map.objects().size(), 1u);
  const std::uint32_t id = ids[0];
  map.observe({ patch(3.0f, -0.8f, 0.5f, 0.4f, 1.0f, ObjectType::glass) }, translation(0, 1, 0), ids);
  ASSERT_EQ(map.objects().size(), 1u);
  EXPECT_EQ(ids[0], id);
  const core::ReflectiveObject pane = rectangle(map, 0);
  EXPECT_NEAR(pane.width, 0.8f, 0.03f);
  EXPECT_NEAR(pane.height, 1.0f, 0.03f);
  EXPECT_NEAR(pane.centre.x(), 3.0f, 1e-3f);
  EXPECT_NEAR(pane.centre.y(), 0.0f, 0.02f);
  EXPECT_NEAR(pane.centre.z(), 0.5f, 0.02f);
  EXPECT_EQ(map.objects()[0].sweeps_seen, 2u);
  EXPECT_EQ(pane.type, ObjectType::glass);
}

TEST(ObjectMap, KeepsApartWhatLiesOnAnotherPlaneOrBeyondTheGap)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  map.observe({ patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  // Parallel, 0.3 m behind: another plane.
  map.observe({ patch(3.3f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  // Same plane, 5 cm beside the first (within merge_gap 0.1): touches.
  map.observe({ patch(3.0f, 0.45f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_EQ(ids[0], 0u);
  // Same plane, 0.5 m beside: another object.
  map.observe({ patch(3.0f, -0.9f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(map.objects().size(), 3u);
  EXPECT_EQ(ids[0], 2u);
  // A broken plane is not placed (and does not take an id).
  core::ReflectiveObject broken = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror);
  broken.plane[0] = std::numeric_limits<float>::quiet_NaN();
  map.observe({ broken }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_EQ(ids[0], core::ObjectMap::kNotMerged);
  EXPECT_EQ(map.objects().size(), 3u);
  // Turned by 30 degrees about z at the same place: not coplanar.
  core::ReflectiveObject turned = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror);
  const Eigen::Vector3f normal = Eigen::AngleAxisf(0.52f, Eigen::Vector3f::UnitZ()) * Eigen::Vector3f(-1, 0, 0);
  turned.plane << normal, -normal.dot(turned.centre);
  turned.width_axis = Eigen::Vector3f::UnitZ().cross(normal).normalized();
  map.observe({ turned }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_EQ(map.objects().size(), 4u);
  EXPECT_EQ(ids[0], 3u);
}

TEST(ObjectMap, APatchBridgingTwoObjectsJoinsThemUnderTheOlderId)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  map.observe({ patch(3.0f, -0.6f, 0.5f, 0.4f, 0.4f, ObjectType::glass),
                patch(3.0f, 0.6f, 0.5f, 0.4f, 0.4f, ObjectType::glass) },
              Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(map.objects().size(), 2u);
  map.observe({ patch(3.0f, 0.0f, 0.5f, 0.9f, 0.4f, ObjectType::glass) }, Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(map.objects().size(), 1u);
  EXPECT_EQ(ids[0], 0u);
  EXPECT_EQ(map.objects()[0].id, 0u);
  EXPECT_NEAR(rectangle(map, 0).width, 1.6f, 0.03f);
  EXPECT_EQ(map.nextId(), 2u);  // the joined id is not handed out again
}

TEST(ObjectMap, TheExtentIsTheUnionOfThePatchesNotTheirBoundingBox)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  // An L: a 1.0 x 0.2 m strip along the bottom and a 0.2 x 1.0 m strip up the left side.
  map.observe({ patch(3.0f, 0.0f, 0.1f, 1.0f, 0.2f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  map.observe({ patch(3.0f, -0.4f, 0.5f, 0.2f, 1.0f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(map.objects().size(), 1u);
  const double cell = map.config().cell_size;
  const double area = static_cast<double>(map.objects()[0].cells.count()) * cell * cell;
  EXPECT_NEAR(area, 0.2 + 0.2 - 0.04, 0.03);  // the L, not the 1 m^2 box around it
  EXPECT_NEAR(rectangle(map, 0).width, 1.0f, 0.03f);
  EXPECT_NEAR(rectangle(map, 0).height, 1.0f, 0.03f);
}

TEST(ObjectMap, TypeLogOddsAccumulatesAndForgettingBoundsItSoAMovedObjectIsRetyped)
{
  core::ObjectMapConfig config = mapConfig();
  config.forgetting = 0.1;
  config.type_log_odds = 1.0;
  core::ObjectMap map(config);
  std::vector<std::uint32_t> ids;
  const core::ReflectiveObject unknown = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::unknown);
  map.observe({ unknown }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_EQ(map.type(map.objects()[0]), ObjectType::unknown);
  map.observe({ patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_DOUBLE_EQ(map.objects()[0].mirror_log_odds, 1.0);
  EXPECT_EQ(map.type(map.objects()[0]), ObjectType::mirror);
  // An unknown sweep only forgets.
  map.observe({ unknown }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_DOUBLE_EQ(map.objects()[0].mirror_log_odds, 0.9);
  for (int k = 0; k < 200; ++k)
    map.observe({ patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_NEAR(map.objects()[0].mirror_log_odds, 10.0, 1e-6);  // 1 / forgetting
  // The mirror is replaced by a pane: L_k = 20 * 0.9^k - 10 reaches -1 at k = 8.
  int glass_sweeps = 0;
  while (map.type(map.objects()[0]) != ObjectType::glass && glass_sweeps < 100)
  {
    map.observe({ patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::glass) }, Eigen::Isometry3d::Identity(), ids);
    ++glass_sweeps;
  }
  EXPECT_EQ(glass_sweeps, 8);
  EXPECT_EQ(map.objects()[0].sweeps_seen, 211u);
  EXPECT_EQ(ids[0], 0u);
}

TEST(ObjectMap, IntensityEvidenceTooWeakForOneSweepAddsUpOverSweeps)
{
  core::ObjectMapConfig config = mapConfig();
  config.forgetting = 0.1;
  config.type_log_odds = 1.0;
  config.intensity_type_log_odds = 2.2;
  core::ObjectMap map(config);
  std::vector<std::uint32_t> ids;
  // Left unknown by the geometry, the intensities say mirror at half the log-odds that would type
  // it in one sweep: +0.5 per sweep, 0.5, 0.95, 1.355: a mirror from the third sweep on.
  core::ReflectiveObject faint_mirror = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::unknown);
  faint_mirror.intensity.log_odds = 1.1f;
  map.observe({ faint_mirror }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_NEAR(map.objects()[0].mirror_log_odds, 0.5, 1e-6);  // 1.1f is not 1.1
  map.observe({ faint_mirror }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_EQ(map.type(map.objects()[0]), ObjectType::unknown);
  map.observe({ faint_mirror }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_NEAR(map.objects()[0].mirror_log_odds, 1.355, 1e-6);
  EXPECT_EQ(map.type(map.objects()[0]), ObjectType::mirror);

  // A type the geometry decided counts +-1 whatever the intensities say; one the intensities
  // typed counts by its log-odds, within +-1.
  core::ObjectMap second(config);
  core::ReflectiveObject geometric_glass = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::glass);
  geometric_glass.intensity.log_odds = 6.0f;
  second.observe({ geometric_glass }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_DOUBLE_EQ(second.objects()[0].mirror_log_odds, -1.0);
  core::ReflectiveObject intensity_glass = patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::glass);
  intensity_glass.intensity.typed = true;
  intensity_glass.intensity.log_odds = -5.0f;
  second.observe({ intensity_glass }, Eigen::Isometry3d::Identity(), ids);
  EXPECT_DOUBLE_EQ(second.objects()[0].mirror_log_odds, -1.9);
}

TEST(ObjectMap, IdsStayWhenTheSensorMovesAndTurns)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  // A mirror at x = 3 of the fixed frame (y in [-0.5, 0.5], z in [0, 1]) and a pane at y = 4.
  // Each sweep's frame is the sensor's: rotated by yaw about z and moved along x.
  for (int k = 0; k < 5; ++k)
  {
    Eigen::Isometry3d fixed_from_sweep = translation(0.3 * k, 0.0, 0.0);
    fixed_from_sweep.rotate(Eigen::AngleAxisd(0.2 * k, Eigen::Vector3d::UnitZ()));
    const Eigen::Isometry3d sweep_from_fixed = fixed_from_sweep.inverse();
    std::vector<core::ReflectiveObject> seen;
    for (const auto& place : { std::make_pair(Eigen::Vector3d(3, 0, 0.5), Eigen::Vector3d(-1, 0, 0)),
                               std::make_pair(Eigen::Vector3d(1.5, 4, 0.5), Eigen::Vector3d(0, -1, 0)) })
    {
      core::ReflectiveObject object;
      object.type = place.second.x() != 0.0 ? ObjectType::mirror : ObjectType::glass;
      const Eigen::Vector3f centre = (sweep_from_fixed * place.first).cast<float>();
      const Eigen::Vector3f normal = (sweep_from_fixed.linear() * place.second).cast<float>();
      object.plane << normal, -normal.dot(centre);
      object.centre = centre;
      object.width_axis = Eigen::Vector3f::UnitZ().cross(normal).normalized();
      object.height_axis = normal.cross(object.width_axis);
      object.width = 0.6f;
      object.height = 0.6f;
      seen.push_back(object);
    }
    map.observe(seen, fixed_from_sweep, ids);
    ASSERT_EQ(ids, (std::vector<std::uint32_t>{ 0, 1 }));
  }
  ASSERT_EQ(map.objects().size(), 2u);
  EXPECT_EQ(map.objects()[0].sweeps_seen, 5u);
  EXPECT_NEAR(map.objects()[0].normal.dot(Eigen::Vector3d(-1, 0, 0)), 1.0, 1e-6);
  EXPECT_NEAR(map.objects()[0].offset, 3.0, 1e-6);
  // Back in a sweep's frame, the plane faces that sweep's sensor.
  const Eigen::Isometry3d sweep_from_fixed = translation(5.0, 0.0, 0.0).inverse();
  const core::ReflectiveObject behind = map.toReflectiveObject(map.objects()[0], sweep_from_fixed, Eigen::Vector3f::Zero());
  EXPECT_GT(behind.signedDistance(Eigen::Vector3f::Zero()), 0.0f);
  EXPECT_NEAR(behind.centre.x(), -2.0f, 1e-3f);
  EXPECT_NEAR(behind.width, 0.6f, 0.03f);
}

TEST(PostFilter, ReplacesEachSweepObjectByItsMapObjectOnceAndAddsTheKnownOnes)
{
  core::ObjectMap map(mapConfig());
  core::PostFilter stage(map);
  core::Sweep sweep;
  core::SweepLabels labels;
  core::ReflectionEvidence evidence;
  core::SweepContext context;
  std::vector<core::ReflectiveObject> objects = { patch(3.0f, -0.6f, 0.5f, 0.4f, 0.4f, ObjectType::glass),
                                                  patch(3.0f, 1.6f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) };
  // Without a fixed pose the sweep stays single-sweep.
  stage.process(sweep, context, evidence, labels, objects);
  EXPECT_TRUE(map.objects().empty());
  ASSERT_EQ(objects.size(), 2u);

  context.has_fixed_pose = true;
  stage.process(sweep, context, evidence, labels, objects);
  ASSERT_EQ(map.objects().size(), 2u);
  // Two patches of the pane this time: they label as one object, the full pane; the mirror is
  // not seen but labels too.
  objects = { patch(3.0f, -0.7f, 0.5f, 0.3f, 0.4f, ObjectType::unknown),
              patch(3.0f, -0.3f, 0.5f, 0.3f, 0.4f, ObjectType::glass) };
  stage.process(sweep, context, evidence, labels, objects);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].type, ObjectType::glass);
  EXPECT_NEAR(objects[0].width, 0.7f, 0.03f);
  EXPECT_EQ(objects[0].surface_inliers.size(), 40u);
  EXPECT_EQ(objects[1].type, ObjectType::mirror);
  EXPECT_NEAR(objects[1].centre.y(), 1.6f, 0.02f);
  EXPECT_EQ(objects[0].id, 0u);
  EXPECT_EQ(objects[1].id, 1u);
  // From a place on the mirror's plane (its cone degenerate) it does not label.
  core::SweepContext on_plane = context;
  on_plane.fixed_from_sweep = translation(3.0, 0.0, 0.0);
  objects.clear();
  stage.process(sweep, on_plane, evidence, labels, objects);
  EXPECT_TRUE(objects.empty());
}

// A mirror beside a doorway: from the first place the sensor faces it (a surface echo), from
// the second it sees it at 20 degrees (no surface echo, only the phantoms behind it).
TEST(PostFilter, PhantomsOfAKnownMirrorAreLabelledInASweepWhereItGaveNoDoubleEcho)
{
  const auto scene = [](float shift_y, float surface_echo_degrees) {
    test::TracedScene scene;
    scene.panels = test::room(2.0f, 2.0f, 3.0f, 1.0f, 1.5f);
    scene.panels.push_back({ 0, 1.99f, { -0.5f, -0.3f }, { 0.5f, 0.7f }, Surface::mirror });
    // The scene in the frame of a sensor at y = shift_y.
    for (Panel& panel : scene.panels)
    {
      if (panel.axis == 1)
        panel.at -= shift_y;
      else
      {
        const int y = panel.axis == 0 ? 0 : 1;  // y's place among the two other axes
        panel.low[y] -= shift_y;
        panel.high[y] -= shift_y;
      }
    }
    scene.surface_echo_degrees = surface_echo_degrees;
    // All round: the phantoms land on the wall behind the sensor, which it must see too.
    return scene.sweep(-180.0f, 179.5f, -30.0f, 40.0f, 0.5f);
  };
  core::Params params;
  params.post_filter = 1;
  params.grow_objects = 1;  // the first sweep sees the whole mirror (its surface echoes are a patch of it)
  core::Pipeline pipeline(params);
  core::SweepContext context;
  context.has_fixed_pose = true;
  const core::PipelineResult& first = pipeline.process(scene(0.0f, 4.0f), context);
  ASSERT_EQ(first.objects.size(), 1u);
  ASSERT_EQ(first.objects[0].type, ObjectType::mirror);
  ASSERT_EQ(pipeline.objectMap().objects().size(), 1u);

  // The second place: 0.7 m to the side, and no surface echo at all.
  const core::Sweep sideways = scene(0.7f, 0.0f);
  core::Pipeline single_sweep{ core::Params() };
  const core::PipelineResult& alone = single_sweep.process(sideways, core::SweepContext());
  EXPECT_TRUE(alone.objects.empty());
  context.fixed_from_sweep = translation(0.0, 0.7, 0.0);
  const core::PipelineResult& second = pipeline.process(sideways, context);
  ASSERT_EQ(second.objects.size(), 1u);
  EXPECT_EQ(second.objects[0].type, ObjectType::mirror);
  // A point beyond the mirror's plane seen through the mirror is a phantom; those seen through the
  // part of it the map knows (the first sweep's grown rectangle) must all be labelled.
  const core::ReflectiveObject& mirror = second.objects[0];
  std::size_t phantoms = 0, labelled = 0, known = 0, known_labelled = 0, labelled_alone = 0;
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t b = 0; b < sideways.beamCount(); ++b)
    {
      const Eigen::Vector3f& p = sideways.echoes[k].points[b];
      if (!p.allFinite() || p.x() < 2.0f)
        continue;
      const Eigen::Vector3f crossing = (1.99f / p.x()) * p;
      if (std::fabs(crossing.y() + 0.7f) > 0.5f || crossing.z() < -0.3f || crossing.z() > 0.7f)
        continue;
      const bool reflective = second.labels.echoes[k][b] == core::Label::behindReflective;
      ++phantoms;
      labelled += reflective ? 1 : 0;
      labelled_alone += alone.labels.echoes[k][b] == core::Label::behindReflective ? 1 : 0;
      const Eigen::Vector3f in_plane = crossing - mirror.centre;
      if (std::fabs(in_plane.dot(mirror.width_axis)) < 0.5f * mirror.width - 0.02f &&
          std::fabs(in_plane.dot(mirror.height_axis)) < 0.5f * mirror.height - 0.02f)
      {
        ++known;
        known_labelled += reflective ? 1 : 0;
      }
    }
  ASSERT_GT(phantoms, 1000u);
  EXPECT_EQ(labelled_alone, 0u);
  EXPECT_GE(static_cast<double>(known_labelled), 0.99 * static_cast<double>(known));
  EXPECT_GE(static_cast<double>(labelled), 0.85 * static_cast<double>(phantoms));
  EXPECT_GT(known, 1000u);
  EXPECT_GT(mirror.phantom_points, 0u);
}

class ObjectMapFile : public ::testing::Test
{
protected:
  void SetUp() override { path_ = "/tmp/test_object_map_" + std::to_string(::getpid()) + ".yaml"; }
  void TearDown() override { std::remove(path_.c_str()); }
  void write(const std::string& text)
  {
    std::ofstream file(path_);
    file << text;
  }
  std::string path_;
};

TEST_F(ObjectMapFile, SavesAndLoadsEveryObjectAsItWas)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  map.observe({ patch(3.0f, 0.0f, 0.1f, 1.0f, 0.2f, ObjectType::mirror),
                patch(3.0f, -3.0f, 0.5f, 0.5f, 1.0f, ObjectType::glass) },
              translation(0.1, 0.2, 0.3), ids);
  map.observe({ patch(3.0f, -0.4f, 0.5f, 0.2f, 1.0f, ObjectType::mirror) }, translation(0.1, 0.2, 0.3), ids);
  ASSERT_EQ(core::saveObjectMap(path_, "odom", map), "");
  core::ObjectMap loaded(mapConfig());
  ASSERT_EQ(core::loadObjectMap(path_, "odom", loaded), "");
  ASSERT_EQ(loaded.objects().size(), 2u);
  EXPECT_EQ(loaded.nextId(), map.nextId());
  for (std::size_t k = 0; k < 2; ++k)
  {
    const core::MapObject& a = map.objects()[k];
    const core::MapObject& b = loaded.objects()[k];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.cells.rows(), b.cells.rows());
    EXPECT_EQ(a.cells.minI(), b.cells.minI());
    EXPECT_EQ(a.cells.minJ(), b.cells.minJ());
    EXPECT_DOUBLE_EQ(a.offset, b.offset);
    EXPECT_DOUBLE_EQ(a.mirror_log_odds, b.mirror_log_odds);
    EXPECT_EQ(a.sweeps_seen, b.sweeps_seen);
    EXPECT_TRUE(a.normal.isApprox(b.normal, 1e-12));
    EXPECT_EQ(a.landing_tolerance.per_range, b.landing_tolerance.per_range);
  }
  // The loaded map goes on merging under the same ids.
  loaded.observe({ patch(3.0f, 0.3f, 0.1f, 0.5f, 0.2f, ObjectType::mirror) }, translation(0.1, 0.2, 0.3), ids);
  EXPECT_EQ(ids[0], map.objects()[0].id);
  EXPECT_EQ(loaded.objects().size(), 2u);
}

TEST_F(ObjectMapFile, ACorruptOrIncompatibleFileGivesAClearErrorAndAnEmptyMap)
{
  core::ObjectMap map(mapConfig());
  std::vector<std::uint32_t> ids;
  map.observe({ patch(3.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::mirror) }, Eigen::Isometry3d::Identity(), ids);
  ASSERT_EQ(core::saveObjectMap(path_, "odom", map), "");
  std::string good;
  {
    std::ifstream file(path_);
    good.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  const auto replaced = [&good](const std::string& from, const std::string& to) {
    std::string text = good;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  };
  struct Case
  {
    std::string text;
    std::string error;  // a part of the message
  };
  const std::vector<Case> cases = {
    { "", "no object map" },
    { "objects: [1, 2", "no YAML" },
    { "- just\n- a list\n", "no object map" },
    { good.substr(0, good.size() / 2), "" },
    { replaced("version: 1", "version: 7"), "version 7" },
    { replaced("fixed_frame: odom", "fixed_frame: map"), "frame 'map'" },
    { replaced("cell_size: 0.025", "cell_size: 0.05"), "map_cell_size" },
    { replaced("sweeps_seen: 1", "sweeps_seen: -4"), "sweeps_seen" },
    { replaced("offset: ", "offset: .nan #"), "not finite" },
    { replaced("offset: ", "offset: [1] #"), "no number" },
    { replaced("normal: [", "normal: [3, "), "normal" },
    { replaced("normal: [", "normal: [2 ,"), "normal" },
    { replaced("rows:", "rows: ['12']\n    old_rows:"), "only 0 and 1" },
    { replaced("id: 0", "idx: 0"), "'id' is missing" },
    { good + "  - " + good.substr(good.find("id: 0")), "" },
  };
  for (const Case& c : cases)
  {
    write(c.text);
    core::ObjectMap loaded(mapConfig());
    std::vector<std::uint32_t> ids_before;
    loaded.observe({ patch(2.0f, 0.0f, 0.5f, 0.4f, 0.4f, ObjectType::glass) }, Eigen::Isometry3d::Identity(), ids_before);
    const std::string error = core::loadObjectMap(path_, "odom", loaded);
    EXPECT_NE(error, "") << c.text;
    EXPECT_NE(error.find(c.error), std::string::npos) << error;
    EXPECT_TRUE(loaded.objects().empty()) << c.text;
  }
  core::ObjectMap missing(mapConfig());
  EXPECT_NE(core::loadObjectMap("/nonexistent/map.yaml", "odom", missing).find("cannot read"), std::string::npos);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
