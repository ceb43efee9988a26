#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <string>

#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using test::Beam;
using test::filled;
using test::kInf;
using test::kNaN;

// A single return, published identically in both echoes.
Beam single(const Eigen::Vector3f& p)
{
  return Beam{ p, p };
}

// A beam whose second echo found nothing.
Beam firstOnly(const Eigen::Vector3f& p)
{
  return Beam{ p, filled(kNaN) };
}

core::Params outlierParams(double radius, int min_neighbors)
{
  core::Params params;
  params.outlier_radius = radius;
  params.outlier_min_neighbors = min_neighbors;
  return params;
}

// The filter as the pipeline builds it from these parameters.
core::OutlierFilter filterFor(const core::Params& params)
{
  return core::OutlierFilter(core::stageConfigs(params).outlier_filter);
}

// Finite points carry `subject`, the others nanPoint, as after the range gate.
core::SweepLabels labelsFor(const core::Sweep& sweep, Label subject = Label::unchecked)
{
  core::SweepLabels labels;
  labels.reset(sweep.beamCount());
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < sweep.beamCount(); ++i)
      labels.echoes[k][i] = sweep.echoes[k].points[i].allFinite() ? subject : Label::nanPoint;
  return labels;
}

// side x side single returns 1 cm apart in the plane x = 3, corner at (3, y0, z0).
std::vector<Beam> patch(int side, float y0 = 0.0f, float z0 = 0.0f)
{
  std::vector<Beam> beams;
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b)
      beams.push_back(single(Eigen::Vector3f(3.0f, y0 + 0.01f * a, z0 + 0.01f * b)));
  return beams;
}

// The contract written the slow, obvious way: every pair of distinct points.
core::SweepLabels bruteForce(const core::Sweep& sweep, const core::Params& params, Label subject,
                             const core::SweepLabels& before, std::size_t& removed)
{
  struct Point
  {
    Eigen::Vector3f p;
    std::size_t beam;
    bool echo[2];
  };
  std::vector<Point> points;
  core::SweepLabels after = before;
  removed = 0;
  for (std::size_t i = 0; i < sweep.beamCount(); ++i)
  {
    bool is_subject[2];
    for (std::size_t k = 0; k < 2; ++k)
    {
      is_subject[k] = before.echoes[k][i] == subject;
      if (is_subject[k] && !sweep.echoes[k].points[i].allFinite())
      {
        after.echoes[k][i] = Label::nanPoint;
        ++removed;
        is_subject[k] = false;
      }
    }
    const Eigen::Vector3f& p1 = sweep.echoes[0].points[i];
    const Eigen::Vector3f& p2 = sweep.echoes[1].points[i];
    if (is_subject[0] && is_subject[1] && p1 == p2)
      points.push_back({ p1, i, { true, true } });
    else
      for (std::size_t k = 0; k < 2; ++k)
        if (is_subject[k])
          points.push_back({ sweep.echoes[k].points[i], i, { k == 0, k == 1 } });
  }
  const float r2 = static_cast<float>(params.outlier_radius * params.outlier_radius);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    int neighbours = 0;
    for (std::size_t j = 0; j < points.size(); ++j)
    {
      const float dx = points[j].p.x() - points[i].p.x();
      const float dy = points[j].p.y() - points[i].p.y();
      const float dz = points[j].p.z() - points[i].p.z();
      if (j != i && dx * dx + dy * dy + dz * dz <= r2)
        ++neighbours;
    }
    if (neighbours >= params.outlier_min_neighbors)
      continue;
    for (std::size_t k = 0; k < 2; ++k)
      if (points[i].echo[k])
      {
        after.echoes[k][points[i].beam] = Label::nanPoint;
        ++removed;
      }
  }
  return after;
}

void expectSameLabels(const core::SweepLabels& actual, const core::SweepLabels& expected)
{
  for (std::size_t k = 0; k < 2; ++k)
  {
    ASSERT_EQ(actual.echoes[k].size(), expected.echoes[k].size());
    for (std::size_t i = 0; i < actual.echoes[k].size(); ++i)
      ASSERT_EQ(actual.echoes[k][i], expected.echoes[k][i]) << "echo " << k + 1 << ", beam " << i;
  }
}

TEST(OutlierFilter, RemovesAnIsolatedPointAndKeepsTheDensePatch)
{
  std::vector<Beam> beams = patch(10);
  beams.push_back(single(Eigen::Vector3f(3.0f, 1.0f, 1.0f)));
  const core::Sweep sweep = test::makeSweep(beams);
  core::SweepLabels labels = labelsFor(sweep);
  EXPECT_EQ(filterFor(outlierParams(0.1, 5)).apply(sweep, Label::unchecked, labels), 2u);
  EXPECT_EQ(labels.echoes[0].back(), Label::nanPoint);
  EXPECT_EQ(labels.echoes[1].back(), Label::nanPoint);
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(labels.count(k, Label::unchecked), 100u) << "echo " << k + 1;
}

TEST(OutlierFilter, KeepsAPointWithExactlyMinNeighborsAndRemovesOneWithOneFewer)
{
  // Centre at (2, 0, 0), neighbours 5 cm away on the axes, n_inlier = 4. The neighbours are
  // 7 to 10 cm apart from each other, so each of them has the centre and at most 3 others.
  const Eigen::Vector3f centre(2.0f, 0.0f, 0.0f);
  const std::vector<Eigen::Vector3f> around = { { 0.0f, 0.05f, 0.0f },
                                                { 0.0f, -0.05f, 0.0f },
                                                { 0.0f, 0.0f, 0.05f },
                                                { 0.0f, 0.0f, -0.05f } };
  for (std::size_t count : { 3u, 4u })
  {
    std::vector<Beam> beams = { firstOnly(centre) };
    for (std::size_t i = 0; i < count; ++i)
      beams.push_back(firstOnly(centre + around[i]));
    const core::Sweep sweep = test::makeSweep(beams);
    core::SweepLabels labels = labelsFor(sweep);
    filterFor(outlierParams(0.1, 4)).apply(sweep, Label::unchecked, labels);
    EXPECT_EQ(labels.echoes[0][0], count == 4 ? Label::unchecked : Label::nanPoint) << count << " neighbours";
  }
}

TEST(OutlierFilter, CountsANeighbourExactlyAtTheRadius)
{
  // Inclusive: 0.5 and 0.25 are exact in float, so the distance is exactly r.
  const core::Sweep sweep = test::makeSweep({ firstOnly(Eigen::Vector3f(4.0f, 0.0f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(4.0f, 0.0f, 0.5f)),
                                              firstOnly(Eigen::Vector3f(4.0f, 10.0f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(4.0f, 10.0f, 0.50390625f)) });
  core::SweepLabels labels = labelsFor(sweep);
  EXPECT_EQ(filterFor(outlierParams(0.5, 1)).apply(sweep, Label::unchecked, labels), 2u);
  EXPECT_EQ(labels.echoes[0][0], Label::unchecked);
  EXPECT_EQ(labels.echoes[0][1], Label::unchecked);
  EXPECT_EQ(labels.echoes[0][2], Label::nanPoint);
  EXPECT_EQ(labels.echoes[0][3], Label::nanPoint);
}

TEST(OutlierFilter, JudgesAndCountsOnlySubjectPoints)
{
  // A dense valid patch with one errorSurface point in it, and a lone valid point: the
  // errorSurface pass sees the errorSurface point alone and leaves every valid point be.
  std::vector<Beam> beams = patch(10);
  beams.push_back(single(Eigen::Vector3f(3.0f, 0.045f, 0.045f)));
  beams.push_back(single(Eigen::Vector3f(3.0f, 5.0f, 5.0f)));
  const core::Sweep sweep = test::makeSweep(beams);
  core::SweepLabels labels = labelsFor(sweep, Label::valid);
  const std::size_t surface = beams.size() - 2;
  labels.echoes[0][surface] = Label::errorSurface;
  labels.echoes[1][surface] = Label::errorSurface;

  EXPECT_EQ(filterFor(outlierParams(0.1, 1)).apply(sweep, Label::errorSurface, labels), 2u);
  EXPECT_EQ(labels.echoes[0][surface], Label::nanPoint);
  EXPECT_EQ(labels.echoes[1][surface], Label::nanPoint);
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(labels.count(k, Label::valid), 101u) << "echo " << k + 1;
}

TEST(OutlierFilter, ASingleReturnInBothEchoesIsOnePoint)
{
  const Eigen::Vector3f a(2.0f, 0.0f, 0.0f);
  const Eigen::Vector3f b(2.0f, 0.05f, 0.0f);
  {
    // Alone: the copy in the other echo is not a neighbour, both copies go.
    const core::Sweep sweep = test::makeSweep({ single(a) });
    core::SweepLabels labels = labelsFor(sweep);
    EXPECT_EQ(filterFor(outlierParams(0.1, 1)).apply(sweep, Label::unchecked, labels), 2u);
    EXPECT_EQ(labels.count(0, Label::nanPoint) + labels.count(1, Label::nanPoint), 2u);
  }
  {
    // Two beams: each has one neighbour (not two), both copies share the decision.
    const core::Sweep sweep = test::makeSweep({ single(a), single(b) });
    core::SweepLabels keep = labelsFor(sweep);
    EXPECT_EQ(filterFor(outlierParams(0.1, 1)).apply(sweep, Label::unchecked, keep), 0u);
    core::SweepLabels drop = labelsFor(sweep);
    EXPECT_EQ(filterFor(outlierParams(0.1, 2)).apply(sweep, Label::unchecked, drop), 4u);
  }
  {
    // A third point near a single return has one neighbour, not two.
    const core::Sweep sweep = test::makeSweep({ single(a), firstOnly(b) });
    core::SweepLabels labels = labelsFor(sweep);
    filterFor(outlierParams(0.1, 2)).apply(sweep, Label::unchecked, labels);
    EXPECT_EQ(labels.echoes[0][1], Label::nanPoint);
  }
  {
    // Equal points of different beams are two points and neighbours of each other.
    const core::Sweep sweep = test::makeSweep({ firstOnly(a), firstOnly(a) });
    core::SweepLabels labels = labelsFor(sweep);
    EXPECT_EQ(filterFor(outlierParams(0.1, 1)).apply(sweep, Label::unchecked, labels), 0u);
  }
  {
    // Only one copy is a subject: it is judged alone, the other copy keeps its label.
    const core::Sweep sweep = test::makeSweep({ single(a) });
    core::SweepLabels labels = labelsFor(sweep);
    labels.echoes[1][0] = Label::valid;
    EXPECT_EQ(filterFor(outlierParams(0.1, 1)).apply(sweep, Label::unchecked, labels), 1u);
    EXPECT_EQ(labels.echoes[0][0], Label::nanPoint);
    EXPECT_EQ(labels.echoes[1][0], Label::valid);
  }
}

TEST(OutlierFilter, DecidesOnTheLabelsBeforeTheCall)
{
  // A chain 6 cm apart with r = 0.1 and n_inlier = 2: only the ends have one neighbour.
  // Removing them first would strip their neighbours down to one, and so on to nothing.
  std::vector<Beam> beams;
  for (int i = 0; i < 6; ++i)
    beams.push_back(single(Eigen::Vector3f(2.0f, 0.06f * i, 0.0f)));
  const core::Sweep sweep = test::makeSweep(beams);
  core::SweepLabels labels = labelsFor(sweep);
  EXPECT_EQ(filterFor(outlierParams(0.1, 2)).apply(sweep, Label::unchecked, labels), 4u);
  for (std::size_t k = 0; k < 2; ++k)
  {
    EXPECT_EQ(labels.echoes[k].front(), Label::nanPoint);
    EXPECT_EQ(labels.echoes[k].back(), Label::nanPoint);
    EXPECT_EQ(labels.count(static_cast<int>(k), Label::unchecked), 4u);
  }
}

TEST(OutlierFilter, RemovesNonFiniteSubjectPointsWithoutCountingThem)
{
  // The point at (2, 0, 0) has two finite neighbours; the non-finite subjects would make
  // it four if they counted.
  const core::Sweep sweep = test::makeSweep({ firstOnly(Eigen::Vector3f(2.0f, 0.0f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(2.0f, 0.01f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(2.0f, 0.0f, 0.01f)),
                                              Beam{ filled(kNaN), filled(kInf) },
                                              Beam{ filled(kInf), Eigen::Vector3f(2.0f, kNaN, 0.0f) } });
  core::SweepLabels labels;
  labels.reset(sweep.beamCount(), Label::unchecked);
  labels.echoes[1][0] = labels.echoes[1][1] = labels.echoes[1][2] = Label::nanPoint;
  EXPECT_EQ(filterFor(outlierParams(0.1, 3)).apply(sweep, Label::unchecked, labels), 7u);
  EXPECT_EQ(labels.count(0, Label::nanPoint), 5u);
  EXPECT_EQ(labels.count(1, Label::nanPoint), 5u);
}

TEST(OutlierFilter, ReturnsHowManyPointsItLabelled)
{
  // Two lone single returns (4 points), one lone first echo, a patch that stays, and a
  // point labelled something else that is not looked at.
  std::vector<Beam> beams = patch(5);
  beams.push_back(single(Eigen::Vector3f(1.0f, 1.0f, 1.0f)));
  beams.push_back(single(Eigen::Vector3f(-1.0f, 1.0f, 1.0f)));
  beams.push_back(firstOnly(Eigen::Vector3f(-1.0f, -1.0f, 1.0f)));
  beams.push_back(firstOnly(Eigen::Vector3f(-1.0f, -1.0f, -1.0f)));
  const core::Sweep sweep = test::makeSweep(beams);
  core::SweepLabels labels = labelsFor(sweep);
  labels.echoes[0].back() = Label::valid;
  core::OutlierFilter filter = filterFor(outlierParams(0.1, 3));
  EXPECT_EQ(filter.apply(sweep, Label::unchecked, labels), 5u);
  EXPECT_EQ(labels.echoes[0].back(), Label::valid);
  // Nothing left to remove the second time round.
  EXPECT_EQ(filter.apply(sweep, Label::unchecked, labels), 0u);
}

TEST(OutlierFilter, HandlesCloudsFarFromTheOriginAndOnNegativeCoordinates)
{
  // Slanted patches at negative coordinates and up to 1000 km apart, far more than the
  // grid's 21-bit reach per axis at r = 0.1 m, plus lone points at huge finite coordinates.
  // Steps of 1/16 m are exact in float even at 1e6.
  std::vector<Beam> beams;
  for (const Eigen::Vector3f& corner : { Eigen::Vector3f(-2.0f, -3.0f, -0.04f), Eigen::Vector3f(-1e6f, -5e5f, -2e3f),
                                         Eigen::Vector3f(1e6f, -5e5f, 7e3f), Eigen::Vector3f(1e6f, 1e6f, 1e6f) })
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b)
        beams.push_back(single(corner + Eigen::Vector3f(0.0625f * a, 0.0625f * (a + b), 0.0625f * b)));
  beams.push_back(single(Eigen::Vector3f(-1e6f, -5e5f, -2e3f - 0.5f)));
  beams.push_back(single(Eigen::Vector3f(3e38f, -3e38f, 0.0f)));
  beams.push_back(single(Eigen::Vector3f(-3e38f, -3e38f, -3e38f)));
  const core::Sweep sweep = test::makeSweep(beams);
  const core::Params params = outlierParams(0.1, 2);

  core::SweepLabels labels = labelsFor(sweep);
  std::size_t expected_removed = 0;
  const core::SweepLabels expected = bruteForce(sweep, params, Label::unchecked, labels, expected_removed);
  EXPECT_EQ(filterFor(params).apply(sweep, Label::unchecked, labels), expected_removed);
  expectSameLabels(labels, expected);
  // Grid neighbours are 8.8 cm apart and every patch point has at least 2 of them.
  EXPECT_EQ(expected_removed, 6u);
}

TEST(OutlierFilter, FindsANeighbourThatFloatRoundingPutsJustBeyondTheRadius)
{
  // Found by search: b - a exceeds r by a few ulps, so a and b fall in grid cells two apart
  // if cells are exactly r wide, yet the float distance test accepts the pair. The first
  // point, far away, anchors the grid at x = 0.
  const double radius = 0.36768966276185722;
  const float a = -0x1.12e0bep-30f;
  const float b = 0x1.7883a4p-2f;
  const core::Sweep sweep = test::makeSweep({ firstOnly(Eigen::Vector3f(0.0f, 10.0f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(a, 0.0f, 0.0f)),
                                              firstOnly(Eigen::Vector3f(b, 0.0f, 0.0f)) });
  core::SweepLabels labels = labelsFor(sweep);
  std::size_t expected_removed = 0;
  const core::SweepLabels expected =
      bruteForce(sweep, outlierParams(radius, 1), Label::unchecked, labels, expected_removed);
  ASSERT_EQ(expected_removed, 1u);  // the pair counts as neighbours
  EXPECT_EQ(filterFor(outlierParams(radius, 1)).apply(sweep, Label::unchecked, labels), 1u);
  expectSameLabels(labels, expected);
}

// A cloud with dense clusters, sparse noise, duplicated single returns, points of other
// labels and a few non-finite subject points.
core::Sweep randomSweep(std::mt19937& rng, std::size_t beams, core::SweepLabels& labels, Label subject)
{
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> spread(0.0f, 0.15f);
  std::vector<Eigen::Vector3f> centres;
  for (int c = 0; c < 8; ++c)
    centres.push_back(Eigen::Vector3f(4.0f * unit(rng) - 2.0f, 4.0f * unit(rng) - 2.0f, 2.0f * unit(rng) - 1.0f));
  auto randomPoint = [&]() -> Eigen::Vector3f {
    if (unit(rng) < 0.2f)
      return Eigen::Vector3f(4.0f * unit(rng) - 2.0f, 4.0f * unit(rng) - 2.0f, 2.0f * unit(rng) - 1.0f);
    const Eigen::Vector3f& centre = centres[static_cast<std::size_t>(unit(rng) * 7.999f)];
    return centre + Eigen::Vector3f(spread(rng), spread(rng), spread(rng));
  };
  std::vector<Beam> list;
  for (std::size_t i = 0; i < beams; ++i)
  {
    const float kind = unit(rng);
    if (kind < 0.5f)
      list.push_back(single(randomPoint()));
    else if (kind < 0.97f)
      list.push_back(Beam{ randomPoint(), randomPoint() });
    else
      list.push_back(Beam{ filled(kNaN), unit(rng) < 0.5f ? filled(kInf) : randomPoint() });
  }
  core::Sweep sweep = test::makeSweep(list);
  labels.reset(sweep.beamCount());
  const Label labels_used[] = { subject, subject, subject, Label::valid, Label::nanPoint };
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < beams; ++i)
      labels.echoes[k][i] = labels_used[static_cast<std::size_t>(unit(rng) * 4.999f)];
  return sweep;
}

TEST(OutlierFilter, AgreesWithBruteForceOnRandomClouds)
{
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> radius(0.02, 0.4);
  std::uniform_int_distribution<int> min_neighbors(1, 60);
  for (int round = 0; round < 12; ++round)
  {
    const Label subject = round % 2 == 0 ? Label::unchecked : Label::errorSurface;
    const std::size_t beams = 1000 + 400 * static_cast<std::size_t>(round);
    core::SweepLabels labels;
    const core::Sweep sweep = randomSweep(rng, beams, labels, subject);
    const core::Params params = outlierParams(radius(rng), min_neighbors(rng));
    std::size_t expected_removed = 0;
    const core::SweepLabels expected = bruteForce(sweep, params, subject, labels, expected_removed);
    SCOPED_TRACE("round " + std::to_string(round) + ", r = " + std::to_string(params.outlier_radius) +
                 ", n = " + std::to_string(params.outlier_min_neighbors));
    EXPECT_EQ(filterFor(params).apply(sweep, subject, labels), expected_removed);
    expectSameLabels(labels, expected);
  }
}

TEST(OutlierFilter, HandlesDegenerateParameters)
{
  // validate() refuses these, but a caller that skips it must not crash or loop.
  std::mt19937 rng(99);
  core::SweepLabels before;
  const core::Sweep sweep = randomSweep(rng, 2000, before, Label::unchecked);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // r = 0 keeps only points repeated exactly in another beam; r = inf makes every point a
  // neighbour of every other; with r = NaN nothing is near; n = INT_MAX removes everything.
  for (const core::Params& params : { outlierParams(0.0, 1), outlierParams(inf, 1500), outlierParams(nan, 1),
                                      outlierParams(0.1, std::numeric_limits<int>::max()) })
  {
    core::SweepLabels labels = before;
    std::size_t expected_removed = 0;
    const core::SweepLabels expected = bruteForce(sweep, params, Label::unchecked, labels, expected_removed);
    SCOPED_TRACE("r = " + std::to_string(params.outlier_radius) + ", n = " + std::to_string(params.outlier_min_neighbors));
    EXPECT_EQ(filterFor(params).apply(sweep, Label::unchecked, labels), expected_removed);
    expectSameLabels(labels, expected);
  }
  {
    // A negative radius holds nothing: every subject point goes.
    core::SweepLabels labels = before;
    const std::size_t subjects = before.count(0, Label::unchecked) + before.count(1, Label::unchecked);
    EXPECT_EQ(filterFor(outlierParams(-0.1, 1)).apply(sweep, Label::unchecked, labels), subjects);
  }
  {
    // n_inlier < 0 is met by every point (0 is automatic).
    core::SweepLabels labels = before;
    EXPECT_EQ(filterFor(outlierParams(0.1, -1)).apply(sweep, Label::unchecked, labels), 0u);
    expectSameLabels(labels, before);
  }
}

TEST(OutlierFilter, GivesTheSameResultWhenReusedAcrossSweepsOfDifferentSizes)
{
  std::mt19937 rng(7);
  const core::Params params = outlierParams(0.1, 8);
  core::OutlierFilter reused = filterFor(params);
  for (std::size_t beams : { 3000u, 200u, 5000u, 0u, 1u, 3000u })
  {
    core::SweepLabels labels;
    const core::Sweep sweep = randomSweep(rng, beams, labels, Label::unchecked);
    core::SweepLabels fresh_labels = labels;
    const std::size_t reused_removed = reused.apply(sweep, Label::unchecked, labels);
    const std::size_t fresh_removed = filterFor(params).apply(sweep, Label::unchecked, fresh_labels);
    EXPECT_EQ(reused_removed, fresh_removed) << beams << " beams";
    expectSameLabels(labels, fresh_labels);
  }
}

}  // namespace
}  // namespace ohm_mirror_detector3d
