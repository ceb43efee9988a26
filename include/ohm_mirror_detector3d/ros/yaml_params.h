// Pre-filter parameters from a YAML file (prefilter_bag --params), read like the nodelet
// reads them from the parameter server after `rosparam load`: the same names, types and
// messages (readParams in parameters.h).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
class YamlParamFile : public ParamSource
{
public:
  // Reads a flat map of parameter names to values, such as launch/*.yaml. Throws
  // std::runtime_error naming the file when it cannot be read or is not such a map.
  explicit YamlParamFile(const std::string& path);

  bool has(const std::string& name) const override;
  // Types as rosparam gives them: a plain scalar such as 5 is an integer (and a number),
  // 0.2, 1e-3, .inf are numbers; quoted scalars, booleans, lists and maps are neither.
  bool get(const std::string& name, double& value) const override;
  bool get(const std::string& name, int& value) const override;
  // Any scalar (input_mode, sweep_frame).
  bool get(const std::string& name, std::string& value) const override;
  // A list of numbers (rotation_axis).
  bool get(const std::string& name, std::vector<double>& value) const override;
  std::string describe(const std::string& name) const override;

  // The names in the file that nothing asked for (misspelt or not used here), in file order.
  std::vector<std::string> unusedNames() const;

private:
  struct Value
  {
    bool scalar = false;  // false for null, lists and maps
    bool plain = false;   // an unquoted scalar: may be a number
    std::string text;
    bool list = false;
    std::vector<Value> items;  // of a list
  };
  const Value* find(const std::string& name) const;

  std::string path_;
  std::vector<std::string> order_;
  std::map<std::string, Value> values_;
  mutable std::set<std::string> asked_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
