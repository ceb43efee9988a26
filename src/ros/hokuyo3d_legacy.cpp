#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
const char* const kEchoArray = "coorddist";

// The field at `path`, which must be an array of `element` (a builtin type).
std::string findArray(const std::map<std::string, FieldLocation>& locations, const std::string& path,
                      const std::string& element, bool required, const FieldLocation*& found)
{
  found = nullptr;
  const auto it = locations.find(path);
  if (it == locations.end())
    return required ? "has no field '" + path + "'" : "";
  const FieldSpec& field = *it->second.field;
  if (!field.is_array || field.type != element)
    return "field '" + path + "' is " + field.typeName() + ", expected " + element + "[]";
  found = &it->second;
  return "";
}

template <typename T>
T readAt(const std::uint8_t* data, std::size_t offset)
{
  T value;
  std::memcpy(&value, data + offset, sizeof(T));
  return value;
}
}  // namespace

const char* const kLegacyScanDatatype = "ohm_hokuyo3d/CoordDistMulti";

std::string legacyLayoutProblem(const std::string& datatype, const std::string& definition)
{
  MessageDefinition parsed;
  const std::string problem = parsed.parse(datatype, definition);
  if (!problem.empty())
    return problem;
  for (const FieldSpec& echoes : parsed.root().fields)
  {
    if (echoes.name != kEchoArray)
      continue;
    if (!echoes.is_array || echoes.nested == nullptr)
      break;
    for (const FieldSpec& coord : echoes.nested->fields)
      if (coord.name == "coord" && !coord.is_array && coord.nested != nullptr)
        for (const FieldSpec& coords : coord.nested->fields)
          if (coords.name == "coords" && coords.typeName() == "float32[]")
            return "";
    return "message definition of " + datatype + " has no field '" + kEchoArray + "[].coord.coords' of type float32[]";
  }
  return "message definition of " + datatype + " has no field '" + kEchoArray + "' that is an array of CoordDist "
         "messages";
}

std::string Hokuyo3dLegacyDecoder::parseDefinition(const std::string& datatype, const std::string& definition)
{
  std::string problem = definition_.parse(datatype, definition);
  if (!problem.empty())
    return problem;
  for (const FieldSpec& field : definition_.root().fields)
  {
    if (field.name != kEchoArray)
      continue;
    if (!field.is_array || field.nested == nullptr)
      return "field '" + field.name + "' of " + datatype + " is " + field.typeName() +
             ", expected an array of CoordDist messages";
    return "";
  }
  return "message definition of " + datatype + " has no field '" + kEchoArray + "' (expected CoordDist[] " +
         kEchoArray + ")";
}

std::string Hokuyo3dLegacyDecoder::decode(const std::string& datatype, const std::string& definition,
                                          const std::uint8_t* data, std::size_t size, core::Sweep& sweep,
                                          std_msgs::Header& header)
{
  if (datatype != datatype_ || definition != definition_text_)
  {
    datatype_ = datatype;
    definition_text_ = definition;
    definition_problem_ = parseDefinition(datatype, definition);
  }
  if (!definition_problem_.empty())
    return definition_problem_;
  std::string problem = walkMessage(definition_, data, size, locations_);
  if (!problem.empty())
    return problem;

  const std::size_t echoes = std::min<std::size_t>(locations_.at(kEchoArray).count, 2);
  if (echoes == 0)
    return std::string("'") + kEchoArray + "' is empty: the message holds no echo";

  // Header of the sweep: that of the first echo's coordinates.
  const std::string header_path = std::string(kEchoArray) + "[0].coord.header";
  const auto stamp = locations_.find(header_path + ".stamp");
  const auto seq = locations_.find(header_path + ".seq");
  const auto frame = locations_.find(header_path + ".frame_id");
  if (stamp == locations_.end() || frame == locations_.end() || stamp->second.field->type != "time" ||
      frame->second.field->type != "string")
    return "has no std_msgs/Header '" + header_path + "' (with 'stamp' and 'frame_id')";
  header.stamp.sec = readAt<std::uint32_t>(data, stamp->second.offset);
  header.stamp.nsec = readAt<std::uint32_t>(data, stamp->second.offset + 4);
  header.seq = seq != locations_.end() && seq->second.field->type == "uint32" ?
                   readAt<std::uint32_t>(data, seq->second.offset) :
                   0;
  header.frame_id.assign(reinterpret_cast<const char*>(data) + frame->second.offset, frame->second.count);
  // The echoes of a beam must be measured in one frame, or comparing their ranges and the
  // back-projection mix two frames (an empty frame_id says nothing).
  const std::string second_frame_path = std::string(kEchoArray) + "[1].coord.header.frame_id";
  const auto second_frame = locations_.find(second_frame_path);
  if (echoes == 2 && second_frame != locations_.end() && second_frame->second.field->type == "string")
  {
    const std::string frame_id(reinterpret_cast<const char*>(data) + second_frame->second.offset,
                               second_frame->second.count);
    if (!frame_id.empty() && !header.frame_id.empty() && frame_id != header.frame_id)
      return "'" + second_frame_path + "' is '" + frame_id + "' but '" + header_path + ".frame_id' is '" +
             header.frame_id + "'; both echoes must be in one frame";
  }

  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::size_t beams = 0;
  bool has_intensity = true;
  for (std::size_t k = 0; k < echoes; ++k)
  {
    const std::string base = std::string(kEchoArray) + "[" + std::to_string(k) + "].";
    const FieldLocation* coords = nullptr;
    const FieldLocation* mask = nullptr;
    const FieldLocation* intensity = nullptr;
    std::string mask_path = base + "coord.mask";
    problem = findArray(locations_, base + "coord.coords", "float32", true, coords);
    if (problem.empty())
      problem = findArray(locations_, mask_path, "bool", false, mask);
    if (problem.empty() && mask == nullptr)
      problem = findArray(locations_, mask_path = base + "dist.mask", "bool", false, mask);
    if (problem.empty())
      problem = findArray(locations_, base + "coord.intensity", "float32", false, intensity);
    if (!problem.empty())
      return problem;
    if (coords->count % 3 != 0)
      return "field '" + base + "coord.coords' holds " + std::to_string(coords->count) +
             " values, not 3 per point";
    const std::size_t n = coords->count / 3;
    if (k == 0)
    {
      beams = n;
      sweep.resize(1, n);
    }
    else if (n != beams)
      return "echo 2 has " + std::to_string(n) + " points but echo 1 has " + std::to_string(beams) +
             "; the echoes must be index-aligned";
    if (mask != nullptr && mask->count != n)
      return "field '" + mask_path + "' holds " + std::to_string(mask->count) + " values for " +
             std::to_string(n) + " points";
    if (intensity != nullptr && intensity->count != n)
      return "field '" + base + "coord.intensity' holds " + std::to_string(intensity->count) + " values for " +
             std::to_string(n) + " points";
    has_intensity = has_intensity && intensity != nullptr;
    core::EchoCloud& echo = sweep.echoes[k];
    for (std::size_t i = 0; i < n; ++i)
    {
      const bool valid = mask == nullptr || data[mask->offset + i] != 0;
      if (valid)
        std::memcpy(echo.points[i].data(), data + coords->offset + 12 * i, 12);
      else
        echo.points[i].setConstant(nan);
      echo.intensities[i] = intensity != nullptr ? readAt<float>(data, intensity->offset + 4 * i) : nan;
    }
  }
  if (echoes == 1)
  {
    // One echo only: every beam is a single-return beam.
    std::fill(sweep.echoes[1].points.begin(), sweep.echoes[1].points.end(), Eigen::Vector3f::Constant(nan));
    std::fill(sweep.echoes[1].intensities.begin(), sweep.echoes[1].intensities.end(), nan);
  }
  sweep.has_intensity = has_intensity;
  sweep.input_cells.clear();
  sweep.computeRanges(Eigen::Vector3f::Zero());
  return "";
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
