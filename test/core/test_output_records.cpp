#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "ohm_mirror_detector3d/core/output_records.h"
#include "sweep_fixtures.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::Label;
using core::OutputRecord;
using test::ahead;

OutputRecord recordAt(const std::vector<std::uint8_t>& bytes, std::size_t i)
{
  OutputRecord record;
  std::memcpy(&record, bytes.data() + i * sizeof(OutputRecord), sizeof(OutputRecord));
  return record;
}

// A buffer of `records` records, filled with garbage so that an unwritten byte shows.
std::vector<std::uint8_t> garbage(std::size_t records)
{
  return std::vector<std::uint8_t>(records * sizeof(OutputRecord), 0xAB);
}

TEST(OutputRecords, AreTheNodeletsTwentyFourBytes)
{
  // x y z intensity (float32) at 0 .. 15, label and echo (uint8) at 16 and 17, beam (uint32) at 20.
  const std::array<core::OutputField, 7>& fields = core::outputFields();
  const char* names[] = { "x", "y", "z", "intensity", "label", "echo", "beam" };
  const std::uint32_t offsets[] = { 0, 4, 8, 12, 16, 17, 20 };
  for (std::size_t k = 0; k < fields.size(); ++k)
  {
    EXPECT_STREQ(fields[k].name, names[k]);
    EXPECT_EQ(fields[k].offset, offsets[k]);
  }
  EXPECT_EQ(fields[0].type, core::OutputFieldType::float32);
  EXPECT_EQ(fields[4].type, core::OutputFieldType::uint8);
  EXPECT_EQ(fields[6].type, core::OutputFieldType::uint32);
  EXPECT_EQ(sizeof(OutputRecord), 24u);
}

TEST(OutputRecords, LabelledHoldsEcho1ThenEcho2InBeamOrderAndEveryByteIsWritten)
{
  const core::Sweep sweep = test::makeSweep({ { ahead(1.0f), ahead(2.0f) }, { ahead(3.0f), ahead(3.0f) } });
  core::SweepLabels labels;
  labels.reset(2);
  labels.echoes[0] = { Label::errorSurface, Label::valid };
  labels.echoes[1] = { Label::error, Label::valid };
  ASSERT_EQ(core::labelledRecordCount(sweep), 4u);
  std::vector<std::uint8_t> bytes = garbage(4);
  core::writeLabelledRecords(sweep, labels, bytes.data());
  const float xs[] = { 1.0f, 3.0f, 2.0f, 3.0f };
  const Label expected[] = { Label::errorSurface, Label::valid, Label::error, Label::valid };
  for (std::size_t i = 0; i < 4; ++i)
  {
    const OutputRecord r = recordAt(bytes, i);
    EXPECT_EQ(r.x, xs[i]);
    EXPECT_EQ(r.y, 0.0f);
    EXPECT_EQ(r.intensity, static_cast<float>(i % 2));  // the fixture's intensity is the beam
    EXPECT_EQ(r.label, static_cast<std::uint8_t>(expected[i]));
    EXPECT_EQ(r.echo, i < 2 ? 1 : 2);
    EXPECT_EQ(r.beam, i % 2);
    EXPECT_EQ(r.padding[0], 0);
    EXPECT_EQ(r.padding[1], 0);
  }
}

TEST(OutputRecords, LabelledKeepsTheInputsOrderAndMarksPointsInNoCell)
{
  // Input point 0 in beam 1 echo 2, point 1 in no cell, point 2 in beam 0 echo 1.
  core::Sweep sweep = test::makeSweep({ { ahead(1.0f), ahead(1.5f) }, { ahead(2.0f), ahead(2.5f) } });
  sweep.unbinned.points = { Eigen::Vector3f(7.0f, 8.0f, 9.0f) };
  sweep.unbinned.intensities = { 42.0f };
  sweep.input_cells = { { 1, 1 }, { 0, core::PointRef::kNoCell }, { 0, 0 } };
  core::SweepLabels labels;
  labels.reset(2, Label::valid);
  ASSERT_EQ(core::labelledRecordCount(sweep), 3u);
  std::vector<std::uint8_t> bytes = garbage(3);
  core::writeLabelledRecords(sweep, labels, bytes.data());
  const OutputRecord first = recordAt(bytes, 0), lost = recordAt(bytes, 1), last = recordAt(bytes, 2);
  EXPECT_EQ(first.x, 2.5f);
  EXPECT_EQ(first.echo, 2);
  EXPECT_EQ(first.beam, 1u);
  EXPECT_EQ(lost.x, 7.0f);
  EXPECT_EQ(lost.intensity, 42.0f);
  EXPECT_EQ(lost.label, static_cast<std::uint8_t>(Label::nanPoint));
  EXPECT_EQ(lost.echo, 0);
  EXPECT_EQ(lost.beam, core::kNoBeam);
  EXPECT_EQ(lost.padding[0] | lost.padding[1], 0);
  EXPECT_EQ(last.x, 1.0f);
  EXPECT_EQ(last.echo, 1);
  EXPECT_EQ(last.beam, 0u);
}

TEST(OutputRecords, CleanedWritesEachPointAsGiven)
{
  const std::vector<core::OutputPoint> points = {
    { Eigen::Vector3f(1.0f, 2.0f, 3.0f), 0.5f, Label::behindReflective, 2, 77 },
    { Eigen::Vector3f(-1.0f, 0.0f, 4.0f), 0.25f, Label::valid, 1, 3 },
  };
  std::vector<std::uint8_t> bytes = garbage(2);
  core::writeCleanedRecords(points, bytes.data());
  const OutputRecord a = recordAt(bytes, 0), b = recordAt(bytes, 1);
  EXPECT_EQ(a.z, 3.0f);
  EXPECT_EQ(a.intensity, 0.5f);
  EXPECT_EQ(a.label, static_cast<std::uint8_t>(Label::behindReflective));
  EXPECT_EQ(a.echo, 2);
  EXPECT_EQ(a.beam, 77u);
  EXPECT_EQ(b.x, -1.0f);
  EXPECT_EQ(b.beam, 3u);
  EXPECT_EQ(a.padding[0] | a.padding[1] | b.padding[0] | b.padding[1], 0);
}

}  // namespace
}  // namespace ohm_mirror_detector3d
