#include "ohm_mirror_detector3d/ros/parameters.h"

#include <boost/any.hpp>

#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "ohm_mirror_detector3d/core/param_table.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
// Reads `name` as T when present. Returns false and explains when it is present but not a T.
template <typename T>
bool readOne(const ParamSource& source, const std::string& name, T& value, bool& present,
             std::vector<std::string>& errors)
{
  present = source.has(name);
  if (!present)
    return true;
  if (source.get(name, value))
    return true;
  // An integer given for a real parameter is fine; get(double) already accepts it.
  errors.push_back("parameter " + source.describe(name) + " has the wrong type: expected " +
                   (std::is_same<T, int>::value ? "an integer" : "a number"));
  return false;
}

// Reads a parameter under every name it is accepted under (core::ParamInfo::names()); the
// first name given wins, and names given with different values are an error.
template <typename T>
void readAliased(const ParamSource& source, const core::ParamInfo& param, T& field, std::vector<std::string>& errors)
{
  const std::vector<std::string> names = param.names();
  std::vector<T> values(names.size(), field);
  std::vector<bool> given(names.size(), false);
  bool ok = true;
  for (std::size_t k = 0; k < names.size(); ++k)
  {
    bool present = false;
    ok = readOne(source, names[k], values[k], present, errors) && ok;
    given[k] = present;
  }
  if (!ok)
    return;
  std::size_t first = names.size();
  for (std::size_t k = 0; k < names.size(); ++k)
  {
    if (!given[k])
      continue;
    if (first == names.size())
      first = k;
    else if (values[k] != values[first])
      errors.push_back("parameters " + names[first] + " = " + std::to_string(values[first]) + " and " + names[k] +
                       " = " + std::to_string(values[k]) + " name the same value and disagree; give only one");
  }
  if (first < names.size())
    field = values[first];
}
// Edits (insert, delete, substitute) between `a` and `b`, ignoring case.
std::size_t editDistance(const std::string& a, const std::string& b)
{
  std::vector<std::size_t> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
  {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
    {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      current[j] = std::min({ previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (same ? 0 : 1) });
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

// A typo is at most this many edits from the name meant.
constexpr std::size_t kTypoEdits = 2;
}  // namespace

std::vector<std::string> unusedParameterWarnings(const std::vector<std::string>& unused, const ParamSource& source,
                                                 const std::string& context)
{
  std::vector<std::string> warnings;
  for (const std::string& name : unused)
  {
    const core::ParamInfo* known = core::findParameter(name);
    if (known != nullptr)
    {
      warnings.push_back("parameter " + source.describe(name) + " is not used with " + context +
                         " and is ignored (it is: " + known->doc + ")");
      continue;
    }
    std::string nearest;
    std::size_t nearest_edits = kTypoEdits + 1;
    for (const core::ParamInfo& param : core::parameterTable())
      for (const std::string& candidate : param.names())
      {
        const std::size_t edits = editDistance(name, candidate);
        if (edits < nearest_edits)
        {
          nearest = candidate;
          nearest_edits = edits;
        }
      }
    warnings.push_back("parameter " + source.describe(name) + " is no parameter of the pre-filter and is ignored (" +
                       (nearest.empty() ? std::string("a typo, or a name of the original node that has no meaning "
                                                      "here") :
                                          "did you mean " + nearest + "?") +
                       ")");
  }
  return warnings;
}

std::vector<std::string> privateParameterNames(const ros::NodeHandle& private_nh)
{
  std::vector<std::string> all;
  std::vector<std::string> names;
  if (!private_nh.getParamNames(all))
    return names;
  const std::string prefix = private_nh.getNamespace() + "/";
  for (const std::string& full : all)
  {
    if (full.compare(0, prefix.size(), prefix) != 0)
      continue;
    const std::string name = full.substr(prefix.size(), full.find('/', prefix.size()) - prefix.size());
    if (!name.empty() && std::find(names.begin(), names.end(), name) == names.end())
      names.push_back(name);
  }
  return names;
}

core::Params readParams(const ParamSource& source, std::vector<std::string>& errors)
{
  core::Params params;
  for (const core::ParamInfo& param : core::parameterTable())
  {
    if (param.real_field != nullptr)
      readAliased(source, param, params.*param.real_field, errors);
    else if (param.integer_field != nullptr)
      readAliased(source, param, params.*param.integer_field, errors);
  }
  return params;
}

core::Params readParams(const ros::NodeHandle& private_nh, std::vector<std::string>& errors)
{
  return readParams(NodeHandleParamSource(private_nh), errors);
}

void writeParams(const ros::NodeHandle& private_nh, const core::Params& params)
{
  for (const core::ParamInfo& param : core::parameterTable())
  {
    if (param.real_field != nullptr)
      private_nh.setParam(param.name, params.*param.real_field);
    else if (param.integer_field != nullptr)
      private_nh.setParam(param.name, params.*param.integer_field);
  }
}

core::Params fromConfig(const PreFilterConfig& config)
{
  core::Params params;
  for (const PreFilterConfig::AbstractParamDescriptionConstPtr& description : PreFilterConfig::__getParamDescriptions__())
  {
    const core::ParamInfo* param = core::findParameter(description->name);
    if (param == nullptr || !param->reconfigurable || param->name != description->name)
      throw std::logic_error("cfg/PreFilter.cfg has the parameter " + description->name +
                             ", which is no reconfigurable parameter of the parameter table");
    boost::any value;
    description->getValue(config, value);
    if (param->real_field != nullptr)
      params.*param->real_field = boost::any_cast<double>(value);
    else
      params.*param->integer_field = boost::any_cast<int>(value);
  }
  return params;
}

std::vector<std::string> keptValues(const PreFilterConfig& kept, const PreFilterConfig& refused)
{
  std::vector<std::string> lines;
  for (const PreFilterConfig::AbstractParamDescriptionConstPtr& description : PreFilterConfig::__getParamDescriptions__())
  {
    boost::any kept_value, refused_value;
    description->getValue(kept, kept_value);
    description->getValue(refused, refused_value);
    std::ostringstream line;
    if (description->type == "double")
    {
      const double a = boost::any_cast<double>(kept_value), b = boost::any_cast<double>(refused_value);
      if (a == b)
        continue;
      line << description->name << " = " << a << " (not " << b << ")";
    }
    else
    {
      const int a = boost::any_cast<int>(kept_value), b = boost::any_cast<int>(refused_value);
      if (a == b)
        continue;
      line << description->name << " = " << a << " (not " << b << ")";
    }
    lines.push_back(line.str());
  }
  return lines;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
