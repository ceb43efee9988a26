#include "ohm_mirror_detector3d/ros/message_walker.h"

#include <cstring>
#include <set>
#include <sstream>

#include "ohm_mirror_detector3d/ros/md5.h"

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
  std::vector<std::string> raw_lines;               // as given, for MessageSpec::text
};

// The section's lines without the blank ones that separate it from the next "MSG:" line.
std::string sectionText(const std::vector<std::string>& raw_lines)
{
  std::size_t end = raw_lines.size();
  while (end > 0 && trim(raw_lines[end - 1]).empty())
    --end;
  std::string text;
  for (std::size_t i = 0; i < end; ++i)
    text += (i > 0 ? "\n" : "") + raw_lines[i];
  return text;
}
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
    sections.back().raw_lines.push_back(raw);
  }
  for (const Section& section : sections)
  {
    if (specs_.count(section.name))
      continue;  // the same type given twice: the first wins
    std::unique_ptr<MessageSpec> spec(new MessageSpec);
    spec->name = section.name;
    spec->text = sectionText(section.raw_lines);
    specs_[section.name] = std::move(spec);
  }

  // Parse the fields of every section, then resolve the nested types.
  for (const Section& section : sections)
  {
    MessageSpec& spec = *specs_[section.name];
    if (!spec.fields.empty() || !spec.constants.empty())
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
      // A constant ("uint8 TYPE_MIRROR=1", "string NAME=a # b"): no bytes in the message. A
      // string's value is the rest of the line (a '#' too), others end at a comment (genmsg).
      const std::size_t equals = rest.find('=');
      const std::size_t hash = rest.find('#');
      if (equals != std::string::npos && (hash == std::string::npos || equals < hash))
      {
        const std::string value = type == "string" ? rest.substr(equals + 1) :
                                                     rest.substr(equals + 1, hash == std::string::npos ?
                                                                                 std::string::npos :
                                                                                 hash - equals - 1);
        spec.constants.push_back(ConstantSpec{ type, trim(rest.substr(0, equals)), trim(value) });
        continue;
      }
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

const MessageSpec* MessageDefinition::find(const std::string& full_name) const
{
  const auto found = specs_.find(full_name);
  return found == specs_.end() ? nullptr : found->second.get();
}

namespace
{
std::string md5sumAt(const MessageSpec& spec, int depth)
{
  if (depth > kMaxDepth)
    return "";
  std::string text;
  for (const ConstantSpec& constant : spec.constants)
    text += constant.type + " " + constant.name + "=" + constant.value + "\n";
  for (const FieldSpec& field : spec.fields)
    text += (field.nested != nullptr ? md5sumAt(*field.nested, depth + 1) : field.typeName()) + " " + field.name + "\n";
  if (!text.empty())
    text.pop_back();
  return md5Hex(text);
}

void collectNested(const MessageSpec& spec, std::vector<const MessageSpec*>& order, std::set<std::string>& seen,
                   int depth)
{
  if (depth > kMaxDepth)
    return;
  for (const FieldSpec& field : spec.fields)
  {
    if (field.nested == nullptr || !seen.insert(field.nested->name).second)
      continue;
    order.push_back(field.nested);
    collectNested(*field.nested, order, seen, depth + 1);
  }
}
}  // namespace

std::string md5sum(const MessageSpec& spec)
{
  return md5sumAt(spec, 0);
}

std::string fullDefinition(const MessageSpec& spec)
{
  std::vector<const MessageSpec*> nested;
  std::set<std::string> seen{ spec.name };
  collectNested(spec, nested, seen, 0);
  std::string text = spec.text + "\n";
  for (const MessageSpec* type : nested)
    text += std::string(80, '=') + "\nMSG: " + type->name + "\n" + type->text + "\n";
  text.pop_back();
  return text;
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

void FieldValues::set(const std::string& path, const std::string& type, const void* data, std::size_t count)
{
  values_[path] = Value{ type, data, count };
}

void FieldValues::setString(const std::string& path, const std::string& text)
{
  values_[path] = Value{ "string", &text, 1 };
}

void FieldValues::setCount(const std::string& path, std::size_t count)
{
  values_[path] = Value{ "", nullptr, count };
}

class MessageSerializer
{
public:
  MessageSerializer(const FieldValues& values, std::vector<std::uint8_t>& bytes) : values_(values.values_), bytes_(bytes)
  {
  }

  std::string write(const MessageSpec& spec, const std::string& prefix, int depth = 0)
  {
    if (depth > kMaxDepth)
      return "'" + prefix + "' is nested deeper than " + std::to_string(kMaxDepth) +
             " levels: is the definition recursive?";
    for (const FieldSpec& field : spec.fields)
    {
      const std::string path = prefix + field.name;
      const auto found = values_.find(path);
      const FieldValues::Value* value = found == values_.end() ? nullptr : &found->second;
      const std::string problem = field.nested != nullptr ? writeMessages(field, path, value, depth) :
                                                            writeBuiltins(field, path, value);
      if (!problem.empty())
        return problem;
    }
    return "";
  }

private:
  // The element count of `field`: its fixed size, else that of its value (none: 0), written
  // as a length prefix.
  std::string count(const FieldSpec& field, const std::string& path, const FieldValues::Value* value,
                    std::size_t& elements)
  {
    if (!field.is_array)
      elements = 1;
    else if (field.array_size >= 0)
      elements = static_cast<std::size_t>(field.array_size);
    else
    {
      elements = value != nullptr ? value->count : 0;
      if (elements > 0xffffffffu)
        return "'" + path + "' has " + std::to_string(elements) + " elements, more than a ROS array holds";
      putLength(elements);
    }
    if (value != nullptr && value->count != elements)
      return "'" + path + "' is " + field.typeName() + " but was given " + std::to_string(value->count) +
             " elements";
    return "";
  }

  std::string writeMessages(const FieldSpec& field, const std::string& path, const FieldValues::Value* value,
                            int depth)
  {
    if (value != nullptr && !value->type.empty())
      return "'" + path + "' is " + field.typeName() + " but was given " + value->type + " values";
    std::size_t elements = 0;
    std::string problem = count(field, path, value, elements);
    for (std::size_t k = 0; k < elements && problem.empty(); ++k)
      problem = write(*field.nested, field.is_array ? path + "[" + std::to_string(k) + "]." : path + ".", depth + 1);
    return problem;
  }

  std::string writeBuiltins(const FieldSpec& field, const std::string& path, const FieldValues::Value* value)
  {
    if (value != nullptr && value->type != field.type)
      return "'" + path + "' is " + field.typeName() + " but was given " +
             (value->type.empty() ? std::string("an element count") : value->type + " values");
    std::size_t elements = 0;
    const std::string problem = count(field, path, value, elements);
    if (!problem.empty())
      return problem;
    if (field.type == "string")
    {
      for (std::size_t k = 0; k < elements; ++k)
      {
        const std::string* text = value != nullptr ? static_cast<const std::string*>(value->data) + k : nullptr;
        putLength(text != nullptr ? text->size() : 0);
        if (text != nullptr)
          bytes_.insert(bytes_.end(), text->begin(), text->end());
      }
      return "";
    }
    const std::size_t size = elements * builtinSize(field.type);
    const std::size_t at = bytes_.size();
    bytes_.resize(at + size);
    if (value != nullptr && size > 0)
      std::memcpy(bytes_.data() + at, value->data, size);
    return "";
  }

  void putLength(std::size_t length)
  {
    const auto value = static_cast<std::uint32_t>(length);
    const std::size_t at = bytes_.size();
    bytes_.resize(at + 4);
    std::memcpy(bytes_.data() + at, &value, 4);  // ROS 1 serialization is little endian
  }

  const std::map<std::string, FieldValues::Value>& values_;
  std::vector<std::uint8_t>& bytes_;
};

std::string serializeMessage(const MessageSpec& spec, const FieldValues& values, std::vector<std::uint8_t>& bytes)
{
  bytes.clear();
  MessageSerializer serializer(values, bytes);
  return serializer.write(spec, "");
}

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
