#include "ohm_mirror_detector3d/ros/point_fields.h"

#include <cstring>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
using sensor_msgs::PointField;

namespace
{
template <typename T>
T readRaw(const std::uint8_t* data)
{
  T value;
  std::memcpy(&value, data, sizeof(T));
  return value;
}
}  // namespace

const PointField* findField(const sensor_msgs::PointCloud2& cloud, const std::string& name)
{
  for (const PointField& field : cloud.fields)
    if (field.name == name)
      return &field;
  return nullptr;
}

std::size_t fieldSize(std::uint8_t datatype)
{
  switch (datatype)
  {
    case PointField::INT8:
    case PointField::UINT8: return 1;
    case PointField::INT16:
    case PointField::UINT16: return 2;
    case PointField::INT32:
    case PointField::UINT32:
    case PointField::FLOAT32: return 4;
    case PointField::FLOAT64: return 8;
    default: return 0;
  }
}

bool isIntegerDatatype(std::uint8_t datatype)
{
  return fieldSize(datatype) != 0 && datatype != PointField::FLOAT32 && datatype != PointField::FLOAT64;
}

float readNumber(const std::uint8_t* data, std::uint8_t datatype)
{
  switch (datatype)
  {
    case PointField::INT8: return static_cast<float>(readRaw<std::int8_t>(data));
    case PointField::UINT8: return static_cast<float>(readRaw<std::uint8_t>(data));
    case PointField::INT16: return static_cast<float>(readRaw<std::int16_t>(data));
    case PointField::UINT16: return static_cast<float>(readRaw<std::uint16_t>(data));
    case PointField::INT32: return static_cast<float>(readRaw<std::int32_t>(data));
    case PointField::UINT32: return static_cast<float>(readRaw<std::uint32_t>(data));
    case PointField::FLOAT32: return readRaw<float>(data);
    default: return static_cast<float>(readRaw<double>(data));
  }
}

std::int64_t readInteger(const std::uint8_t* data, std::uint8_t datatype)
{
  switch (datatype)
  {
    case PointField::INT8: return readRaw<std::int8_t>(data);
    case PointField::UINT8: return readRaw<std::uint8_t>(data);
    case PointField::INT16: return readRaw<std::int16_t>(data);
    case PointField::UINT16: return readRaw<std::uint16_t>(data);
    case PointField::INT32: return readRaw<std::int32_t>(data);
    case PointField::UINT32: return readRaw<std::uint32_t>(data);
    default: return static_cast<std::int64_t>(readNumber(data, datatype));
  }
}

std::string checkField(const PointField* field, const std::string& name, std::uint32_t point_step, bool float32_only)
{
  if (field == nullptr)
    return "has no '" + name + "' field";
  if (float32_only && field->datatype != PointField::FLOAT32)
    return "field '" + name + "' has datatype " + std::to_string(field->datatype) + ", expected FLOAT32 (7)";
  const std::size_t size = fieldSize(field->datatype);
  if (size == 0)
    return "field '" + name + "' has unknown datatype " + std::to_string(field->datatype);
  if (field->offset + size > point_step)
    return "field '" + name + "' at offset " + std::to_string(field->offset) + " does not fit in point_step " +
           std::to_string(point_step);
  return "";
}

std::string checkCloudLayout(const sensor_msgs::PointCloud2& cloud)
{
  if (cloud.is_bigendian)
    return "is big-endian, which is not supported";
  const std::size_t points = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (points > 0 && cloud.row_step < static_cast<std::uint64_t>(cloud.width) * cloud.point_step)
    return "row_step " + std::to_string(cloud.row_step) + " is smaller than width * point_step = " +
           std::to_string(static_cast<std::uint64_t>(cloud.width) * cloud.point_step);
  const std::uint64_t expected_bytes = static_cast<std::uint64_t>(cloud.row_step) * cloud.height;
  if (points > 0 && cloud.data.size() != expected_bytes)
    return "data holds " + std::to_string(cloud.data.size()) + " bytes but height * row_step = " +
           std::to_string(expected_bytes);
  return "";
}

std::string readIntegerField(const sensor_msgs::PointCloud2& cloud, const std::string& what,
                             const std::vector<std::string>& names, std::vector<std::int64_t>& values,
                             std::string& used_name)
{
  const PointField* field = nullptr;
  for (const std::string& name : names)
    if ((field = findField(cloud, name)) != nullptr)
    {
      used_name = name;
      break;
    }
  if (field == nullptr)
  {
    std::string listed;
    for (std::size_t k = 0; k < names.size(); ++k)
      listed += std::string(k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + "'" + names[k] + "'";
    return "has no " + what + " field (looked for " + listed + ")";
  }
  std::string problem = checkCloudLayout(cloud);
  if (problem.empty())
    problem = checkField(field, used_name, cloud.point_step, false);
  if (!problem.empty())
    return problem;
  if (!isIntegerDatatype(field->datatype))
    return "field '" + used_name + "' has datatype " + std::to_string(field->datatype) +
           ", expected an integer type (INT8 .. UINT32)";
  values.resize(static_cast<std::size_t>(cloud.width) * cloud.height);
  std::size_t i = 0;
  // No point, no loop: an empty cloud may claim 2^32 - 1 rows of width 0.
  const std::uint32_t rows = values.empty() ? 0 : cloud.height;
  for (std::uint32_t row = 0; row < rows; ++row)
  {
    const std::uint8_t* point = cloud.data.data() + static_cast<std::size_t>(row) * cloud.row_step + field->offset;
    for (std::uint32_t col = 0; col < cloud.width; ++col, ++i, point += cloud.point_step)
      values[i] = readInteger(point, field->datatype);
  }
  return "";
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
