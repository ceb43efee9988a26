#include "ohm_mirror_detector3d/core/object_map_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// A bad entry: what and where, for the message.
struct BadEntry : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

const YAML::Node field(const YAML::Node& node, const std::string& key, const std::string& where)
{
  if (!node.IsMap() || !node[key])
    throw BadEntry(where + ": '" + key + "' is missing");
  return node[key];
}

double finiteValue(const YAML::Node& value, const std::string& what)
{
  double number = 0.0;
  try
  {
    number = value.as<double>();
  }
  catch (const YAML::Exception&)
  {
    throw BadEntry(what + " is no number");
  }
  if (!std::isfinite(number))
    throw BadEntry(what + " is not finite");
  return number;
}

double finite(const YAML::Node& node, const std::string& key, const std::string& where)
{
  return finiteValue(field(node, key, where), where + ": '" + key + "'");
}

long long integer(const YAML::Node& node, const std::string& key, const std::string& where, long long lowest,
                  long long highest)
{
  const double number = finite(node, key, where);
  if (number != std::floor(number) || number < static_cast<double>(lowest) || number > static_cast<double>(highest))
    throw BadEntry(where + ": '" + key + "' must be a whole number in [" + std::to_string(lowest) + ", " +
                   std::to_string(highest) + "]");
  return static_cast<long long>(number);
}

Eigen::Vector3d vector3(const YAML::Node& node, const std::string& key, const std::string& where)
{
  const YAML::Node value = field(node, key, where);
  if (!value.IsSequence() || value.size() != 3)
    throw BadEntry(where + ": '" + key + "' must be three numbers");
  Eigen::Vector3d v;
  for (std::size_t k = 0; k < 3; ++k)
    v[static_cast<int>(k)] = finiteValue(value[k], where + ": '" + key + "'");
  return v;
}

std::string text(const YAML::Node& node, const std::string& key, const std::string& where)
{
  const YAML::Node value = field(node, key, where);
  if (!value.IsScalar())
    throw BadEntry(where + ": '" + key + "' must be text");
  return value.Scalar();
}

// Writes doubles so that they read back exactly.
YAML::Emitter& precise(YAML::Emitter& out)
{
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  out.SetFloatPrecision(std::numeric_limits<float>::max_digits10);
  return out;
}

void writeVector(YAML::Emitter& out, const char* key, const Eigen::Vector3d& v)
{
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z() << YAML::EndSeq;
}

MapObject readObject(const YAML::Node& node, const std::string& where)
{
  MapObject object;
  object.id = static_cast<std::uint32_t>(integer(node, "id", where, 0, std::numeric_limits<std::uint32_t>::max() - 1));
  object.normal = vector3(node, "normal", where);
  if (std::fabs(object.normal.norm() - 1.0) > 1e-3)
    throw BadEntry(where + ": 'normal' is no unit vector");
  object.normal.normalize();
  object.offset = finite(node, "offset", where);
  object.origin = vector3(node, "origin", where);
  object.plane_weight = finite(node, "plane_weight", where);
  object.mirror_log_odds = finite(node, "mirror_log_odds", where);
  object.sweeps_seen =
      static_cast<std::uint32_t>(integer(node, "sweeps_seen", where, 0, std::numeric_limits<std::uint32_t>::max()));
  object.footprint = static_cast<float>(finite(node, "footprint", where));
  const YAML::Node tolerance = field(node, "landing_tolerance", where);
  object.landing_tolerance.base = static_cast<float>(finite(tolerance, "base", where + ": landing_tolerance"));
  object.landing_tolerance.per_range = static_cast<float>(finite(tolerance, "per_range", where + ": landing_tolerance"));
  object.landing_tolerance.per_behind =
      static_cast<float>(finite(tolerance, "per_behind", where + ": landing_tolerance"));
  if (object.plane_weight < 0.0 || object.footprint < 0.0f)
    throw BadEntry(where + ": 'plane_weight' and 'footprint' must not be negative");
  const YAML::Node cells = field(node, "cells", where);
  constexpr long long kCellLimit = 1 << 24;
  const int i0 = static_cast<int>(integer(cells, "i0", where + ": cells", -kCellLimit, kCellLimit));
  const int j0 = static_cast<int>(integer(cells, "j0", where + ": cells", -kCellLimit, kCellLimit));
  const YAML::Node rows = field(cells, "rows", where + ": cells");
  if (!rows.IsSequence() || rows.size() == 0)
    throw BadEntry(where + ": cells: 'rows' must be a list of rows of 0 and 1");
  std::vector<std::string> row_texts;
  for (const YAML::Node& row : rows)
  {
    if (!row.IsScalar())
      throw BadEntry(where + ": cells: 'rows' must be a list of rows of 0 and 1");
    row_texts.push_back(row.Scalar());
  }
  if (!object.cells.setRows(i0, j0, row_texts) || object.cells.empty())
    throw BadEntry(where + ": cells: 'rows' must hold only 0 and 1, at least one 1");
  return object;
}
}  // namespace

std::string saveObjectMap(const std::string& path, const std::string& fixed_frame, const ObjectMap& map)
{
  YAML::Emitter out;
  precise(out);
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << kObjectMapFormat;
  out << YAML::Key << "version" << YAML::Value << kObjectMapVersion;
  out << YAML::Key << "fixed_frame" << YAML::Value << fixed_frame;
  out << YAML::Key << "cell_size" << YAML::Value << map.config().cell_size;
  out << YAML::Key << "next_id" << YAML::Value << map.nextId();
  out << YAML::Key << "objects" << YAML::Value << YAML::BeginSeq;
  for (const MapObject& object : map.objects())
  {
    out << YAML::BeginMap;
    out << YAML::Key << "id" << YAML::Value << object.id;
    out << YAML::Key << "type" << YAML::Value << objectTypeName(map.type(object));  // for readers; not read back
    writeVector(out, "normal", object.normal);
    out << YAML::Key << "offset" << YAML::Value << object.offset;
    writeVector(out, "origin", object.origin);
    out << YAML::Key << "plane_weight" << YAML::Value << object.plane_weight;
    out << YAML::Key << "mirror_log_odds" << YAML::Value << object.mirror_log_odds;
    out << YAML::Key << "sweeps_seen" << YAML::Value << object.sweeps_seen;
    out << YAML::Key << "footprint" << YAML::Value << object.footprint;
    out << YAML::Key << "landing_tolerance" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "base" << YAML::Value << object.landing_tolerance.base;
    out << YAML::Key << "per_range" << YAML::Value << object.landing_tolerance.per_range;
    out << YAML::Key << "per_behind" << YAML::Value << object.landing_tolerance.per_behind;
    out << YAML::EndMap;
    out << YAML::Key << "cells" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "i0" << YAML::Value << object.cells.minI();
    out << YAML::Key << "j0" << YAML::Value << object.cells.minJ();
    out << YAML::Key << "rows" << YAML::Value << YAML::BeginSeq;
    for (const std::string& row : object.cells.rows())
      out << YAML::SingleQuoted << row;
    out << YAML::EndSeq << YAML::EndMap;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  if (!out.good())
    return "cannot write the object map: " + out.GetLastError();
  std::ofstream file(path);
  file << out.c_str() << "\n";
  file.close();
  if (!file)
    return "cannot write the object map to '" + path + "'";
  return "";
}

std::string loadObjectMap(const std::string& path, const std::string& fixed_frame, ObjectMap& map)
{
  map.clear();
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::BadFile&)
  {
    return "cannot read the object map '" + path + "'";
  }
  catch (const YAML::Exception& e)
  {
    return "the object map '" + path + "' is no YAML: " + e.what();
  }
  const std::string where = "the object map '" + path + "'";
  try
  {
    if (!root.IsMap() || !root["format"] || !root["format"].IsScalar() || root["format"].Scalar() != kObjectMapFormat)
      return where + " is no object map (its 'format' is not " + kObjectMapFormat + ")";
    const long long version = integer(root, "version", where, 0, std::numeric_limits<int>::max());
    if (version != kObjectMapVersion)
      return where + " has version " + std::to_string(version) + ", this build reads version " +
             std::to_string(kObjectMapVersion);
    const std::string frame = text(root, "fixed_frame", where);
    if (frame != fixed_frame)
      return where + " is in the frame '" + frame + "', the post-filter's fixed_frame is '" + fixed_frame + "'";
    const double cell_size = finite(root, "cell_size", where);
    if (std::fabs(cell_size - map.config().cell_size) > 1e-9 * map.config().cell_size)
    {
      std::ostringstream message;
      message << where << " has cells of " << cell_size << " m, map_cell_size is " << map.config().cell_size << " m";
      return message.str();
    }
    const std::uint32_t next_id =
        static_cast<std::uint32_t>(integer(root, "next_id", where, 0, std::numeric_limits<std::uint32_t>::max()));
    const YAML::Node entries = field(root, "objects", where);
    if (!entries.IsSequence())
      return where + ": 'objects' must be a list";
    std::vector<MapObject> objects;
    for (std::size_t k = 0; k < entries.size(); ++k)
    {
      objects.push_back(readObject(entries[k], where + ", object " + std::to_string(k)));
      for (std::size_t other = 0; other + 1 < objects.size(); ++other)
        if (objects[other].id == objects.back().id)
          return where + ", object " + std::to_string(k) + ": the id " + std::to_string(objects.back().id) +
                 " is taken";
    }
    map.assign(std::move(objects), next_id);
  }
  catch (const BadEntry& e)
  {
    return e.what();
  }
  catch (const YAML::Exception& e)
  {
    return where + ": " + e.what();
  }
  return "";
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
