// The ROS input adapters without a master: field reading and the errors that name the field.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/ros/dual_return.h"

namespace ohm_mirror_detector3d
{
namespace
{
using sensor_msgs::PointField;

struct FieldSpec
{
  const char* name;
  std::uint8_t datatype;
};

// A 1 x n cloud with the given fields packed in order; values[i][f] is field f of point i.
sensor_msgs::PointCloud2 makeCloud(const std::vector<FieldSpec>& fields, const std::vector<std::vector<double>>& values)
{
  sensor_msgs::PointCloud2 cloud;
  std::uint32_t offset = 0;
  for (const FieldSpec& spec : fields)
  {
    PointField field;
    field.name = spec.name;
    field.datatype = spec.datatype;
    field.offset = offset;
    field.count = 1;
    cloud.fields.push_back(field);
    offset += spec.datatype == PointField::FLOAT64 ? 8 : spec.datatype <= PointField::UINT8 ? 1
                                                      : spec.datatype <= PointField::UINT16 ? 2 : 4;
  }
  cloud.point_step = offset;
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(values.size());
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.assign(cloud.row_step, 0);
  for (std::size_t i = 0; i < values.size(); ++i)
    for (std::size_t f = 0; f < fields.size(); ++f)
    {
      std::uint8_t* out = cloud.data.data() + i * cloud.point_step + cloud.fields[f].offset;
      const double v = values[i][f];
      switch (fields[f].datatype)
      {
        case PointField::INT8: { const std::int8_t x = static_cast<std::int8_t>(v); std::memcpy(out, &x, 1); break; }
        case PointField::UINT8: { const auto x = static_cast<std::uint8_t>(v); std::memcpy(out, &x, 1); break; }
        case PointField::INT16: { const std::int16_t x = static_cast<std::int16_t>(v); std::memcpy(out, &x, 2); break; }
        case PointField::UINT16: { const auto x = static_cast<std::uint16_t>(v); std::memcpy(out, &x, 2); break; }
        case PointField::INT32: { const std::int32_t x = static_cast<std::int32_t>(v); std::memcpy(out, &x, 4); break; }
        case PointField::UINT32: { const auto x = static_cast<std::uint32_t>(v); std::memcpy(out, &x, 4); break; }
        case PointField::FLOAT32: { const float x = static_cast<float>(v); std::memcpy(out, &x, 4); break; }
        default: std::memcpy(out, &v, 8);
      }
    }
  return cloud;
}

const FieldSpec kX{ "x", PointField::FLOAT32 }, kY{ "y", PointField::FLOAT32 }, kZ{ "z", PointField::FLOAT32 };

TEST(DualReturnCloud, ReadsEveryIntegerTypeAndTheAlternativeFieldNames)
{
  const std::vector<std::vector<double>> values = { { 3.0, 0.0, 0.0, 0, 7 }, { 5.0, 0.0, 0.0, 1, 7 } };
  for (const char* return_name : { "return", "return_type", "echo" })
    for (const char* ring_name : { "ring", "channel" })
      for (std::uint8_t type : { PointField::INT8, PointField::UINT8, PointField::INT16, PointField::UINT16,
                                 PointField::INT32, PointField::UINT32 })
      {
        const sensor_msgs::PointCloud2 cloud =
            makeCloud({ kX, kY, kZ, { return_name, type }, { ring_name, type } }, values);
        core::DualReturnInput input;
        core::DualReturnBinner binner;
        core::Sweep sweep;
        core::DualReturnStats stats;
        ASSERT_EQ(ros_io::dualReturnCloudToSweep(cloud, 1.0, input, binner, sweep, stats), "")
            << return_name << " " << ring_name << " " << int(type);
        EXPECT_EQ(stats.return_base, 0);
        EXPECT_EQ(stats.paired_beams, 1u);
        EXPECT_EQ(sweep.rows, 8u);
        EXPECT_FALSE(sweep.has_intensity);
      }
}

TEST(DualReturnCloud, MissingOrMistypedFieldsAreNamed)
{
  const std::vector<std::vector<double>> one = { { 3.0, 0.0, 0.0, 1, 0 } };
  core::DualReturnInput input;
  core::DualReturnBinner binner;
  core::Sweep sweep;
  core::DualReturnStats stats;
  const FieldSpec ring{ "ring", PointField::UINT16 }, ret{ "return", PointField::UINT8 };
  EXPECT_EQ(ros_io::dualReturnCloudToSweep(makeCloud({ kX, kY, kZ, { "intensity", PointField::FLOAT32 }, ring }, one),
                                           1.0, input, binner, sweep, stats),
            "has no return-index field (looked for 'return', 'return_type' or 'echo')");
  EXPECT_EQ(ros_io::dualReturnCloudToSweep(makeCloud({ kX, kY, kZ, ret, { "line", PointField::UINT8 } }, one), 1.0,
                                           input, binner, sweep, stats),
            "has no ring field (looked for 'ring' or 'channel')");
  EXPECT_EQ(ros_io::dualReturnCloudToSweep(makeCloud({ kX, kY, kZ, { "return", PointField::FLOAT32 }, ring }, one),
                                           1.0, input, binner, sweep, stats),
            "field 'return' has datatype 7, expected an integer type (INT8 .. UINT32)");
  EXPECT_EQ(ros_io::dualReturnCloudToSweep(makeCloud({ kX, kY, ret, ring }, one), 1.0, input, binner, sweep, stats),
            "has no 'z' field");
}

TEST(DualReturnCloud, UnbinnedPointsAreDescribedWithTheirReasons)
{
  core::DualReturnStats stats;
  stats.points = 10;
  stats.no_return = 3;
  stats.azimuth_resolution_deg = 0.2;
  EXPECT_EQ(core::describeUnbinned(stats), "");  // non-finite points are normal
  stats.duplicates = 2;
  stats.return_out_of_range = 1;
  const std::string text = core::describeUnbinned(stats);
  EXPECT_NE(text.find("6 of 10 points"), std::string::npos) << text;
  EXPECT_NE(text.find("2 sharing a ring and azimuth bin"), std::string::npos) << text;
  EXPECT_NE(text.find("azimuth_resolution_deg = 0.2"), std::string::npos) << text;
  EXPECT_NE(text.find("1 with a return index other than 1 or 2"), std::string::npos) << text;
}

}  // namespace
}  // namespace ohm_mirror_detector3d
