#include "ohm_mirror_detector3d/ros/yaml_params.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
bool parseInteger(const std::string& text, int& value)
{
  std::size_t i = (!text.empty() && (text[0] == '+' || text[0] == '-')) ? 1 : 0;
  if (i == text.size())
    return false;
  for (std::size_t k = i; k < text.size(); ++k)
    if (text[k] < '0' || text[k] > '9')
      return false;
  errno = 0;
  const long parsed = std::strtol(text.c_str(), nullptr, 10);
  if (errno == ERANGE || parsed < INT_MIN || parsed > INT_MAX)
    return false;
  value = static_cast<int>(parsed);
  return true;
}

bool parseNumber(const std::string& text, double& value)
{
  // YAML's special floats.
  static const char* const kInf[] = { ".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF" };
  static const char* const kMinusInf[] = { "-.inf", "-.Inf", "-.INF" };
  static const char* const kNan[] = { ".nan", ".NaN", ".NAN" };
  for (const char* s : kInf)
    if (text == s)
      return value = std::numeric_limits<double>::infinity(), true;
  for (const char* s : kMinusInf)
    if (text == s)
      return value = -std::numeric_limits<double>::infinity(), true;
  for (const char* s : kNan)
    if (text == s)
      return value = std::numeric_limits<double>::quiet_NaN(), true;
  // Decimal notation only: strtod would also take "inf", "nan" and hexadecimal.
  bool digit = false;
  for (char c : text)
  {
    if (c >= '0' && c <= '9')
      digit = true;
    else if (c != '.' && c != 'e' && c != 'E' && c != '+' && c != '-')
      return false;
  }
  if (!digit)
    return false;
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE)
    return false;
  value = parsed;
  return true;
}
}  // namespace

YamlParamFile::YamlParamFile(const std::string& path) : path_(path)
{
  if (!std::ifstream(path).good())
    throw std::runtime_error("cannot read parameter file " + path);
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw std::runtime_error("parameter file " + path + " is not valid YAML: " + e.what());
  }
  if (root.IsNull())
    return;  // an empty file sets nothing
  if (!root.IsMap())
    throw std::runtime_error("parameter file " + path + " must be a map of parameter names to values");
  const auto toValue = [](const YAML::Node& node) {
    Value value;
    value.scalar = node.IsScalar();
    if (value.scalar)
    {
      value.text = node.Scalar();
      // yaml-cpp tags plain scalars "?" and quoted ones "!".
      value.plain = node.Tag() != "!";
    }
    return value;
  };
  for (const auto& entry : root)
  {
    const std::string name = entry.first.as<std::string>();
    Value value = toValue(entry.second);
    value.list = entry.second.IsSequence();
    if (value.list)
      for (const auto& item : entry.second)
        value.items.push_back(toValue(item));
    if (values_.count(name) == 0)
      order_.push_back(name);
    values_[name] = value;
  }
}

const YamlParamFile::Value* YamlParamFile::find(const std::string& name) const
{
  asked_.insert(name);
  const auto it = values_.find(name);
  return it == values_.end() ? nullptr : &it->second;
}

bool YamlParamFile::has(const std::string& name) const
{
  return find(name) != nullptr;
}

bool YamlParamFile::get(const std::string& name, double& value) const
{
  const Value* v = find(name);
  return v != nullptr && v->scalar && v->plain && parseNumber(v->text, value);
}

bool YamlParamFile::get(const std::string& name, int& value) const
{
  const Value* v = find(name);
  return v != nullptr && v->scalar && v->plain && parseInteger(v->text, value);
}

bool YamlParamFile::get(const std::string& name, std::string& value) const
{
  const Value* v = find(name);
  if (v == nullptr || !v->scalar)
    return false;
  value = v->text;
  return true;
}

bool YamlParamFile::get(const std::string& name, std::vector<double>& value) const
{
  const Value* v = find(name);
  if (v == nullptr || !v->list)
    return false;
  std::vector<double> numbers(v->items.size());
  for (std::size_t i = 0; i < numbers.size(); ++i)
    if (!v->items[i].scalar || !v->items[i].plain || !parseNumber(v->items[i].text, numbers[i]))
      return false;
  value = numbers;
  return true;
}

std::string YamlParamFile::describe(const std::string& name) const
{
  return name + " (in " + path_ + ")";
}

std::vector<std::string> YamlParamFile::unusedNames() const
{
  std::vector<std::string> unused;
  for (const std::string& name : order_)
    if (asked_.count(name) == 0)
      unused.push_back(name);
  return unused;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
