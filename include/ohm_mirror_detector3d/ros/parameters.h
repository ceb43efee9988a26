// Pre-filter parameters on the ROS parameter server and in dynamic_reconfigure.
#pragma once

#include <ros/node_handle.h>

#include <set>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/PreFilterConfig.h"
#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// Where pipeline parameters are read from: the parameter server (the nodelet) or a YAML
// file (prefilter_bag). Both go through readParams below, so they accept the same names
// and types and refuse bad values with the same messages.
class ParamSource
{
public:
  virtual ~ParamSource() = default;
  virtual bool has(const std::string& name) const = 0;
  // False when the value is not of that type (an integer is a number, a number is not an
  // integer), as ros::NodeHandle::getParam.
  virtual bool get(const std::string& name, double& value) const = 0;
  virtual bool get(const std::string& name, int& value) const = 0;
  // False when the value is not a string, or not a list of numbers.
  virtual bool get(const std::string& name, std::string& value) const = 0;
  virtual bool get(const std::string& name, std::vector<double>& value) const = 0;
  // How messages name the parameter, e.g. its resolved name.
  virtual std::string describe(const std::string& name) const = 0;
};

// The parameter server under a node's private namespace; names are described resolved.
class NodeHandleParamSource : public ParamSource
{
public:
  explicit NodeHandleParamSource(const ros::NodeHandle& nh) : nh_(nh) {}
  bool has(const std::string& name) const override { return nh_.hasParam(name); }
  bool get(const std::string& name, double& value) const override { return nh_.getParam(name, value); }
  bool get(const std::string& name, int& value) const override { return nh_.getParam(name, value); }
  bool get(const std::string& name, std::string& value) const override { return nh_.getParam(name, value); }
  bool get(const std::string& name, std::vector<double>& value) const override { return nh_.getParam(name, value); }
  std::string describe(const std::string& name) const override { return nh_.resolveName(name); }

private:
  const ros::NodeHandle& nh_;
};

// A source that remembers every name asked for through it, so that the parameters that are set
// but that no reader asked for can be named (unusedParameterWarnings).
class RecordingParamSource : public ParamSource
{
public:
  explicit RecordingParamSource(const ParamSource& source) : source_(source) {}
  bool has(const std::string& name) const override { return asked(name).has(name); }
  bool get(const std::string& name, double& value) const override { return asked(name).get(name, value); }
  bool get(const std::string& name, int& value) const override { return asked(name).get(name, value); }
  bool get(const std::string& name, std::string& value) const override { return asked(name).get(name, value); }
  bool get(const std::string& name, std::vector<double>& value) const override { return asked(name).get(name, value); }
  std::string describe(const std::string& name) const override { return source_.describe(name); }

  // For a parameter that other code reads itself (diagnostic_updater: diagnostic_period).
  void markUsed(const std::string& name) const { asked_.insert(name); }
  bool wasAsked(const std::string& name) const { return asked_.count(name) > 0; }

private:
  const ParamSource& asked(const std::string& name) const
  {
    asked_.insert(name);
    return source_;
  }

  const ParamSource& source_;
  mutable std::set<std::string> asked_;
};

// One warning per name in `unused` (parameters that are set but that nothing read): a parameter
// of the table that `context` (e.g. "input_mode pair") does not use, saying what it is for; or a
// name that is no parameter of the pre-filter (a typo, with the known name it is nearest to, or
// a name of the original node that has no meaning here). Names are shown by source.describe().
std::vector<std::string> unusedParameterWarnings(const std::vector<std::string>& unused, const ParamSource& source,
                                                 const std::string& context);

// The parameters set under `private_nh`'s namespace (top-level names, without the namespace).
std::vector<std::string> privateParameterNames(const ros::NodeHandle& private_nh);

core::Params readParams(const ParamSource& source, std::vector<std::string>& errors);

// Reads every pipeline parameter of the parameter table (core/param_table.h) from `private_nh`,
// under any name it is accepted under: its original launch file name (e.g.
// `outlierFilter_searchRadius`), its paper symbol (e.g. `r`) or an alias; absent ones keep their
// defaults. Appends to `errors` a message for each value that cannot be read (wrong type, two
// names given with different values). Range checks are Params::validate()'s job.
core::Params readParams(const ros::NodeHandle& private_nh, std::vector<std::string>& errors);

// Writes the parameters back under their original names, so that the dynamic_reconfigure
// server starts from what was read (including values given under other names).
void writeParams(const ros::NodeHandle& private_nh, const core::Params& params);

// The parameters of a dynamic_reconfigure request, matched to the table by name (throws
// std::logic_error should cfg/PreFilter.cfg name a parameter the table does not have as
// reconfigurable; test_parameters keeps the two equal).
core::Params fromConfig(const PreFilterConfig& config);

// "NAME = KEPT (not REFUSED)" for every parameter whose value differs between `kept` and
// `refused`: what a refused reconfigure left in force, for its log line.
std::vector<std::string> keptValues(const PreFilterConfig& kept, const PreFilterConfig& refused);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
