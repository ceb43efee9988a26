#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "ohm_mirror_detector3d/core/parallel.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "traced_scene.h"

namespace ohm_mirror_detector3d
{
namespace
{
using test::Panel;
using test::Surface;

TEST(RunTasks, RunsEveryTaskOnceOnAWorkerOfItsOwnRange)
{
  for (const int threads : { 1, 2, 3, 8 })
  {
    SCOPED_TRACE(threads);
    const std::size_t tasks = 37;
    const std::size_t workers = core::workersFor(tasks, threads);
    EXPECT_EQ(workers, static_cast<std::size_t>(threads));
    std::vector<int> runs(tasks, 0);  // each task writes its own
    std::vector<std::size_t> worker_of(tasks, workers);
    core::runTasks(tasks, threads, [&](std::size_t t, std::size_t worker) {
      ++runs[t];
      worker_of[t] = worker;
    });
    for (std::size_t t = 0; t < tasks; ++t)
    {
      EXPECT_EQ(runs[t], 1);
      EXPECT_LT(worker_of[t], workers);
    }
  }
  EXPECT_EQ(core::workersFor(2, 8), 2u);
  EXPECT_EQ(core::workersFor(0, 8), 1u);
  EXPECT_EQ(core::workersFor(5, 0), 1u);
}

TEST(RunTasks, ATaskThatThrowsIsRethrownAfterTheOthersRan)
{
  for (const int threads : { 1, 3 })
  {
    SCOPED_TRACE(threads);
    std::atomic<int> ran{ 0 };
    EXPECT_THROW(core::runTasks(10, threads,
                                [&](std::size_t t, std::size_t) {
                                  if (t == 4)
                                    throw std::runtime_error("task 4");
                                  ++ran;
                                }),
                 std::runtime_error);
    // One after the other, the first failure ends the loop; side by side, the others still run.
    EXPECT_GE(ran.load(), 4);
  }
}

TEST(RunTasks, PipelinesInSeveralThreadsAndTasksThatStartTasksAllFinish)
{
  // Two callers at once: one gets the pool, the other runs its tasks itself; a task that starts
  // tasks of its own finds the pool busy and runs them itself. Every task runs once either way.
  std::vector<int> outer(64, 0), inner(64 * 8, 0);
  auto work = [&](std::size_t offset) {
    core::runTasks(32, 2, [&](std::size_t t, std::size_t) {
      ++outer[offset + t];
      core::runTasks(8, 2, [&](std::size_t u, std::size_t) { ++inner[(offset + t) * 8 + u]; });
    });
  };
  std::thread other([&]() { work(32); });
  work(0);
  other.join();
  for (const int runs : outer)
    EXPECT_EQ(runs, 1);
  for (const int runs : inner)
    EXPECT_EQ(runs, 1);
}

// A room with a mirror on its back wall, another on its side wall, and a pane in its front wall
// with a room behind it: objects of each type, points behind each of them, and phantoms whose
// beams meet both mirrors.
core::Sweep roomWithMirrorsAndAPane()
{
  test::TracedScene scene;
  scene.panels = test::room(2.5f, 6.0f, 3.0f, 1.0f, 1.5f);
  // The front wall x = 3 around a 2.4 x 1.5 m opening that holds the pane.
  scene.panels.push_back({ 0, 3.0f, { -3.0f, -1.0f }, { -1.2f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, 3.0f, { 1.2f, -1.0f }, { 3.0f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, 3.0f, { -1.2f, -1.0f }, { 1.2f, -0.5f }, Surface::wall });
  scene.panels.push_back({ 0, 3.0f, { -1.2f, 1.0f }, { 1.2f, 1.5f }, Surface::wall });
  scene.panels.push_back({ 0, 3.0f, { -1.2f, -0.5f }, { 1.2f, 1.0f }, Surface::glass });
  scene.panels.push_back({ 0, -2.49f, { -0.6f, -0.4f }, { 0.6f, 0.6f }, Surface::mirror });
  scene.panels.push_back({ 1, -2.99f, { -0.7f, -0.4f }, { 0.7f, 0.6f }, Surface::mirror });
  // A box in the room for the mirrors to show.
  scene.panels.push_back({ 1, 1.0f, { 0.5f, -1.0f }, { 1.5f, 0.2f }, Surface::wall });
  return scene.sweep(-180.0f, 179.5f, -60.0f, 60.0f, 0.5f);
}

void expectSameObject(const core::ReflectiveObject& a, const core::ReflectiveObject& b)
{
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.plane, b.plane);
  EXPECT_EQ(a.centre, b.centre);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.surface_points, b.surface_points);
  EXPECT_EQ(a.behind_points, b.behind_points);
  EXPECT_EQ(a.phantom_points, b.phantom_points);
  EXPECT_EQ(a.transmitted_points, b.transmitted_points);
  EXPECT_EQ(a.ambiguous_points, b.ambiguous_points);
  EXPECT_EQ(a.undecided_points, b.undecided_points);
  EXPECT_EQ(a.evidence.tested_points, b.evidence.tested_points);
  EXPECT_EQ(a.evidence.phantom_points, b.evidence.phantom_points);
  EXPECT_EQ(a.evidence.transmitted_points, b.evidence.transmitted_points);
  EXPECT_EQ(a.evidence.plane_refined, b.evidence.plane_refined);
  EXPECT_EQ(a.landing_tolerance.per_behind, b.landing_tolerance.per_behind);
}

TEST(Pipeline, GivesTheSameLabelsObjectsAndCleanedPointsWithAnyNumberOfThreads)
{
  const core::Sweep sweep = roomWithMirrorsAndAPane();
  core::Params params;
  params.threads = 1;
  core::Pipeline one(params);
  const core::PipelineResult reference = one.process(sweep, core::SweepContext());
  // The scene exercises what the threads share: several objects, each with points behind it.
  ASSERT_GE(reference.objects.size(), 3u);
  std::size_t with_points_behind = 0;
  for (const core::ReflectiveObject& object : reference.objects)
    with_points_behind += object.behind_points > 100 ? 1 : 0;
  ASSERT_GE(with_points_behind, 3u);
  for (const int threads : { 2, 3, 7 })
  {
    SCOPED_TRACE(threads);
    params.threads = threads;
    core::Pipeline many(params);
    const core::PipelineResult& result = many.process(sweep, core::SweepContext());
    EXPECT_EQ(result.labels.echoes[0], reference.labels.echoes[0]);
    EXPECT_EQ(result.labels.echoes[1], reference.labels.echoes[1]);
    EXPECT_EQ(result.assignment.echoes[0], reference.assignment.echoes[0]);
    EXPECT_EQ(result.assignment.echoes[1], reference.assignment.echoes[1]);
    ASSERT_EQ(result.objects.size(), reference.objects.size());
    for (std::size_t j = 0; j < result.objects.size(); ++j)
      expectSameObject(result.objects[j], reference.objects[j]);
    ASSERT_EQ(result.cleaned.size(), reference.cleaned.size());
    for (std::size_t i = 0; i < result.cleaned.size(); ++i)
    {
      EXPECT_EQ(result.cleaned[i].position, reference.cleaned[i].position) << "cleaned point " << i;
      EXPECT_EQ(result.cleaned[i].label, reference.cleaned[i].label) << "cleaned point " << i;
    }
  }
}

}  // namespace
}  // namespace ohm_mirror_detector3d
