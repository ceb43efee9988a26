#include "ohm_mirror_detector3d/ros/parameters.h"

#include <boost/any.hpp>

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
}  // namespace

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

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
