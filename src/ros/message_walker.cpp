#include "ohm_mirror_detector3d/ros/message_walker.h"

#include <cstring>
#include <sstream>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
const char* const kSeparator = "==========";
constexpr int kMaxDepth = 32;

std::string trim(const std::string& text)
{
  const std::size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos)
    return "";
  const std::size_t end = text.find_last_not_of(" \t\r");
  return text.substr(begin, end - begin + 1);
}

std::string packageOf(const std::string& full_name)
{
  const std::size_t slash = full_name.find('/');
  return slash == std::string::npos ? "" : full_name.substr(0, slash);
}

// The field and constant lines of one message section.
struct Section
{
  std::string name;
  std::vector<std::pair<int, std::string>> lines;  // (line number in the text, line)
};
}  // namespace

std::size_t builtinSize(const std::string& type)
{
  if (type == "bool" || type == "int8" || type == "uint8" || type == "byte" || type == "char")
    return 1;
  if (type == "int16" || type == "uint16")
    return 2;
  if (type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "int64" || type == "uint64" || type == "float64" || type == "time" || type == "duration")
    return 8;
  return 0;
}

bool isBuiltin(const std::string& type)
{
  return builtinSize(type) != 0 || type == "string";
}

std::string FieldSpec::typeName() const
{
  if (!is_array)
    return type;
  return type + "[" + (array_size >= 0 ? std::to_string(array_size) : "") + "]";
}

std::string MessageDefinition::parse(const std::string& datatype, const std::string& text)
{
  datatype_ = datatype;
  specs_.clear();
  root_ = nullptr;

  // Split into sections: the main message, then "MSG: pkg/Type" sections.
  std::vector<Section> sections(1);
  sections[0].name = datatype;
  std::istringstream stream(text);
  std::string raw;
  int line_number = 0;
  while (std::getline(stream, raw))
  {
    ++line_number;
    const std::string line = trim(raw);
    if (line.compare(0, std::strlen(kSeparator), kSeparator) == 0)
      continue;
    if (line.compare(0, 4, "MSG:") == 0)
    {
      sections.emplace_back();
      sections.back().name = trim(line.substr(4));
      continue;
    }
    sections.back().lines.emplace_back(line_number, line);
  }
  for (const Section& section : sections)
  {
    if (specs_.count(section.name))
      continue;  // the same type given twice: the first wins
    std::unique_ptr<MessageSpec> spec(new MessageSpec);
    spec->name = section.name;
    specs_[section.name] = std::move(spec);
  }

  // Parse the fields of every section, then resolve the nested types.
  for (const Section& section : sections)
  {
    MessageSpec& spec = *specs_[section.name];
    if (!spec.fields.empty())
      continue;
    for (const auto& numbered : section.lines)
    {
      std::string line = numbered.second;
      const std::string where = "line " + std::to_string(numbered.first) + " ('" + line + "') of " + section.name;
      std::istringstream words(line);
      std::string type, rest;
      words >> type;
      if (type.empty() || type[0] == '#')
        continue;
      std::getline(words, rest);
      rest = trim(rest);
      // A constant ("uint8 TYPE_MIRROR=1", "string NAME=a # b"): no bytes in the message.
      const std::size_t equals = rest.find('=');
      const std::size_t hash = rest.find('#');
      if (equals != std::string::npos && (hash == std::string::npos || equals < hash))
        continue;
      if (hash != std::string::npos)
        rest = trim(rest.substr(0, hash));
      if (rest.empty() || rest.find_first_of(" \t") != std::string::npos)
        return "cannot read " + where + ": expected 'type name'";
      FieldSpec field;
      field.name = rest;
      const std::size_t bracket = type.find('[');
      if (bracket != std::string::npos)
      {
        if (type.back() != ']')
          return "cannot read " + where + ": malformed array type";
        field.is_array = true;
        const std::string size = type.substr(bracket + 1, type.size() - bracket - 2);
        if (!size.empty())
        {
          if (size.find_first_not_of("0123456789") != std::string::npos)
            return "cannot read " + where + ": malformed array size '" + size + "'";
          field.array_size = std::stoll(size);
        }
        type = type.substr(0, bracket);
      }
      if (!isBuiltin(type))
      {
        // Message types: "Header" is std_msgs/Header, a bare name is in the section's package.
        std::string full = type;
        if (type == "Header")
          full = "std_msgs/Header";
        else if (type.find('/') == std::string::npos)
          full = packageOf(section.name) + "/" + type;
        auto found = specs_.find(full);
        if (found == specs_.end())
          return "message definition of " + datatype + " uses type '" + type + "' (" + where +
                 ") but has no 'MSG: " + full + "' section";
        field.nested = found->second.get();
        type = full;
      }
      field.type = type;
      spec.fields.push_back(field);
    }
  }
  root_ = specs_[datatype].get();
  return "";
}

namespace
{
class Walker
{
public:
  Walker(const std::uint8_t* data, std::size_t size, std::map<std::string, FieldLocation>& locations)
    : data_(data), size_(size), locations_(locations)
  {
  }

  std::string walk(const MessageSpec& spec, const std::string& prefix, int depth = 0)
  {
    if (depth > kMaxDepth)
      return "'" + prefix + "' is nested deeper than " + std::to_string(kMaxDepth) +
             " levels: is the definition recursive?";
    for (const FieldSpec& field : spec.fields)
    {
      const std::string path = prefix + field.name;
      std::size_t count = 1;
      if (field.is_array)
      {
        if (field.array_size >= 0)
          count = static_cast<std::size_t>(field.array_size);
        else
        {
          std::uint32_t length = 0;
          const std::string problem = readLength(path, length);
          if (!problem.empty())
            return problem;
          count = length;
        }
      }
      FieldLocation location;
      location.field = &field;
      location.offset = position_;
      location.count = count;
      if (field.nested != nullptr)
      {
        locations_[path] = location;
        for (std::size_t k = 0; k < count; ++k)
        {
          const std::string element = field.is_array ? path + "[" + std::to_string(k) + "]." : path + ".";
          const std::string problem = walk(*field.nested, element, depth + 1);
          if (!problem.empty())
            return problem;
        }
      }
      else if (field.type == "string")
      {
        for (std::size_t k = 0; k < count; ++k)
        {
          std::uint32_t length = 0;
          const std::string element = field.is_array ? path + "[" + std::to_string(k) + "]" : path;
          std::string problem = readLength(element, length);
          if (problem.empty())
            problem = skip(element, length);
          if (!problem.empty())
            return problem;
          if (!field.is_array)
            location = FieldLocation{ &field, position_ - length, length };
        }
        locations_[path] = location;
      }
      else
      {
        const std::size_t element_size = builtinSize(field.type);
        if (count > (size_ - position_) / element_size)
          return ends(path, count * element_size);
        locations_[path] = location;
        position_ += count * element_size;
      }
    }
    return "";
  }

  std::string finish() const
  {
    if (position_ != size_)
      return "the message has " + std::to_string(size_ - position_) +
             " bytes left over after its last field: its definition does not match its bytes";
    return "";
  }

private:
  std::string ends(const std::string& path, std::size_t needed) const
  {
    return "the message ends inside '" + path + "' (at byte " + std::to_string(position_) + " of " +
           std::to_string(size_) + ", " + std::to_string(needed) +
           " more needed): its definition does not match its bytes";
  }

  std::string readLength(const std::string& path, std::uint32_t& length)
  {
    if (size_ - position_ < 4)
      return ends(path, 4);
    std::memcpy(&length, data_ + position_, 4);  // ROS 1 serialization is little endian
    position_ += 4;
    return "";
  }

  std::string skip(const std::string& path, std::size_t bytes)
  {
    if (size_ - position_ < bytes)
      return ends(path, bytes);
    position_ += bytes;
    return "";
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t position_ = 0;
  std::map<std::string, FieldLocation>& locations_;
};
}  // namespace

std::string walkMessage(const MessageDefinition& definition, const std::uint8_t* data, std::size_t size,
                        std::map<std::string, FieldLocation>& locations)
{
  locations.clear();
  Walker walker(data, size, locations);
  const std::string problem = walker.walk(definition.root(), "");
  return problem.empty() ? walker.finish() : problem;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
