// ProcessingStats, what the nodelet reports on /diagnostics, without a master: levels,
// counts and the reset of the per-period values.
#include <gtest/gtest.h>

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <map>
#include <string>

#include "ohm_mirror_detector3d/ros/processing_stats.h"

namespace ohm_mirror_detector3d
{
namespace
{
using diagnostic_msgs::DiagnosticStatus;

struct Report
{
  int level;
  std::string message;
  std::map<std::string, std::string> values;
};

Report report(ros_io::ProcessingStats& stats, bool subscribed = true)
{
  diagnostic_updater::DiagnosticStatusWrapper status;
  stats.report(status, subscribed);
  Report out{ status.level, status.message, {} };
  for (const auto& pair : status.values)
    out.values[pair.key] = pair.value;
  return out;
}

TEST(ProcessingStats, IdleWithoutSubscriberAndWaitingWhenSubscribed)
{
  ros_io::ProcessingStats stats;
  const Report idle = report(stats, false);
  EXPECT_EQ(idle.level, DiagnosticStatus::OK);
  EXPECT_NE(idle.message.find("idle"), std::string::npos);
  EXPECT_EQ(idle.values.at("input subscribed"), "False");
  EXPECT_NE(report(stats, true).message.find("waiting for input"), std::string::npos);
}

TEST(ProcessingStats, ReportsTimesObjectsAndTotals)
{
  ros_io::ProcessingStats stats;
  stats.recordProcessed(0.010, 2, 1000);
  stats.recordProcessed(0.030, 1, 500);
  const Report first = report(stats);
  EXPECT_EQ(first.level, DiagnosticStatus::OK);
  EXPECT_EQ(first.values.at("sweeps processed"), "2");
  EXPECT_EQ(first.values.at("inputs dropped"), "0");
  EXPECT_EQ(first.values.at("mean processing time (ms)"), "20.00");
  EXPECT_EQ(first.values.at("max processing time (ms)"), "30.00");
  EXPECT_EQ(first.values.at("last processing time (ms)"), "30.00");
  EXPECT_EQ(first.values.at("objects in last sweep"), "1");
  EXPECT_EQ(first.values.at("points in last sweep"), "500");
  EXPECT_GT(std::stod(first.values.at("input rate (sweeps/s)")), 0.0);

  // A new period: the totals stay, the period's mean and max start again.
  const Report second = report(stats);
  EXPECT_EQ(second.values.at("sweeps processed"), "2");
  EXPECT_EQ(second.values.at("mean processing time (ms)"), "0.00");
  EXPECT_EQ(second.values.at("max processing time (ms)"), "0.00");
  EXPECT_EQ(second.values.at("input rate (sweeps/s)"), "0.000");
  EXPECT_NE(second.message.find("waiting for input"), std::string::npos);
}

TEST(ProcessingStats, WarnsWhileAStageRemovesAnImplausibleShare)
{
  ros_io::ProcessingStats stats;
  const std::string text = "the outlier filter removed 74.0 % of the points in range (25160 of 34000) with "
                           "outlierFilter_searchRadius = 0.1 m, outlierFilter_minNeighbors = 50 points";
  stats.recordProcessed(0.01, 0, 10);
  stats.recordImplausibleRemoval(text);
  stats.recordProcessed(0.01, 0, 10);
  const Report warned = report(stats);
  EXPECT_EQ(warned.level, DiagnosticStatus::WARN);
  EXPECT_NE(warned.message.find("in 1 of 2 sweeps " + text), std::string::npos) << warned.message;
  EXPECT_EQ(warned.values.at("last implausible removal"), text);

  // The next period without one is OK again; the last one stays on record.
  stats.recordProcessed(0.01, 0, 10);
  const Report next = report(stats);
  EXPECT_EQ(next.level, DiagnosticStatus::OK);
  EXPECT_EQ(next.values.at("last implausible removal"), text);
}

TEST(ProcessingStats, WarnsOnSomeDroppedInputsAndErrsWhenAllAre)
{
  ros_io::ProcessingStats stats;
  stats.recordProcessed(0.01, 0, 10);
  stats.recordDropped("echo1 has 3 points but echo2 has 2");
  const Report some = report(stats);
  EXPECT_EQ(some.level, DiagnosticStatus::WARN);
  EXPECT_NE(some.message.find("1 of 2 inputs dropped"), std::string::npos);
  EXPECT_EQ(some.values.at("last drop reason"), "echo1 has 3 points but echo2 has 2");

  stats.recordDropped("no x field");
  const Report all = report(stats);
  EXPECT_EQ(all.level, DiagnosticStatus::ERROR);
  EXPECT_NE(all.message.find("no x field"), std::string::npos);
  EXPECT_EQ(all.values.at("inputs dropped"), "2");

  // Once good sweeps come again, the level recovers; the reason of the last drop stays visible.
  stats.recordProcessed(0.01, 0, 10);
  const Report recovered = report(stats);
  EXPECT_EQ(recovered.level, DiagnosticStatus::OK);
  EXPECT_EQ(recovered.values.at("last drop reason"), "no x field");
}

}  // namespace
}  // namespace ohm_mirror_detector3d
