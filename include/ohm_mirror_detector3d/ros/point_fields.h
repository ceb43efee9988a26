// Reading PointCloud2 fields by name: shared by the input adapters.
#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// The field called `name`, or nullptr.
const sensor_msgs::PointField* findField(const sensor_msgs::PointCloud2& cloud, const std::string& name);

// Bytes of one value of a PointField datatype; 0 for an unknown datatype.
std::size_t fieldSize(std::uint8_t datatype);

bool isIntegerDatatype(std::uint8_t datatype);

// The value at `data` of the given datatype (little endian), as float / as integer.
float readNumber(const std::uint8_t* data, std::uint8_t datatype);
std::int64_t readInteger(const std::uint8_t* data, std::uint8_t datatype);

// Empty when `field` (found under `name`) exists, has a known datatype (FLOAT32 only when
// float32_only) and fits into a point; otherwise what is wrong, naming the field.
std::string checkField(const sensor_msgs::PointField* field, const std::string& name, std::uint32_t point_step,
                       bool float32_only);

// Empty when the cloud's endianness, row_step and data size are consistent; otherwise why not.
std::string checkCloudLayout(const sensor_msgs::PointCloud2& cloud);

// Reads the first of `names` that the cloud has, which must be an integer field, into
// `values` (one per point, row-major). Returns the problem, naming the field, or `what`
// and the names looked for; `used_name` gets the field's name.
std::string readIntegerField(const sensor_msgs::PointCloud2& cloud, const std::string& what,
                             const std::vector<std::string>& names, std::vector<std::int64_t>& values,
                             std::string& used_name);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
