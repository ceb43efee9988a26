// Every parameter of the pre-filter as data (the rows of parameters.def): the pipeline's, which
// core::Params holds and every front end reads and reconfigures, and the start-up parameters of
// the front ends (input mode, frames, topic names, ...), so that one list knows every name.
//
// The front ends take their names, types, defaults and checks from here: the ROS parameter
// reading (ros/parameters.h), the Python bindings and dataclass (ohm_mirror_detector3d.core),
// and, checked by tests, cfg/PreFilter.cfg and the README's tables.
#pragma once

#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace core
{
enum class ParamType
{
  real,       // double
  integer,    // int
  text,       // string
  real_list,  // list of doubles
};

// Who reads a parameter.
enum class ParamScope
{
  pipeline,    // a field of core::Params: every front end, reconfigurable at run time
  core_input,  // a core input adapter at start-up: the node, prefilter_bag and the Python API
  ros_input,   // the ROS input at start-up (input mode, tf frames, scan assembly): node, prefilter_bag
  node,        // the node only, at start-up (topic names, diagnostics)
};

const char* paramTypeName(ParamType type);    // "real", "integer", "text", "real_list"
const char* paramScopeName(ParamScope scope);  // "pipeline", "core_input", "ros_input", "node"

// One end of an allowed range.
struct ParamBound
{
  bool present = false;
  double value = 0.0;
  bool inclusive = false;
};

// A default: a number (real, integer), a text (text, real_list), or for texts whose default
// is empty, what leaving them empty means.
struct ParamDefault
{
  double number = 0.0;
  const char* text = "";
  const char* when_unset = "";
};

struct ParamInfo
{
  const char* name;      // the ROS name (the original launch file's), cfg and Python field name
  const char* symbol;    // the paper's symbol, "" when none
  std::vector<std::string> aliases;  // further accepted names
  const char* label;     // how messages name it beside `name`
  ParamType type;
  ParamScope scope;
  bool reconfigurable;   // by dynamic_reconfigure; start-up only otherwise
  ParamDefault default_value;
  ParamBound lower;
  ParamBound upper;
  const char* above;     // "" or the name of a parameter this one must be greater than
  const char* unit;      // "m", "m^2", "points", "deg", "s" or ""
  const char* doc;       // one line, Markdown
  const char* allowed;   // for non-numbers: what is allowed, in words
  const char* checked_by;  // the code that checks the value
  // A start-up number the core checks: "" when the value is usable, otherwise why not (null
  // for the others, which their readers check).
  std::string (*check)(double value);
  // The field of core::Params by its C++ name ("" for start-up parameters) and its member
  // pointer (the one of its type; both null for start-up parameters).
  const char* field;
  double Params::*real_field;
  int Params::*integer_field;
  // For a pipeline parameter whose default follows the sensor: what it follows when it is not
  // set (its value is then kAutomatic); "" for the others.
  const char* automatic;

  // name, then symbol, then aliases: every name it is accepted under.
  std::vector<std::string> names() const;
  double value(const Params& params) const;  // pipeline parameters only
  // Whether `params` leave it to the sensor (an automatic parameter at kAutomatic).
  bool isAutomatic(const Params& params) const;
};

// Every parameter, in the order of parameters.def: the pipeline's first.
const std::vector<ParamInfo>& parameterTable();

// The parameter accepted under `name` (its name, symbol or an alias); null when none.
const ParamInfo* findParameter(const std::string& name);

}  // namespace core
}  // namespace ohm_mirror_detector3d
