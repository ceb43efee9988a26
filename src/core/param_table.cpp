#include "ohm_mirror_detector3d/core/param_table.h"

#include <cmath>
#include <sstream>

#include "ohm_mirror_detector3d/core/dual_return.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// The words parameters.def's rows are written in.
constexpr ParamBound unbounded()
{
  return ParamBound{};
}
constexpr ParamBound atLeast(double value)
{
  return ParamBound{ true, value, true };
}
constexpr ParamBound above(double value)
{
  return ParamBound{ true, value, false };
}
constexpr ParamBound atMost(double value)
{
  return ParamBound{ true, value, true };
}
constexpr ParamDefault number(double value)
{
  return ParamDefault{ value, "", "" };
}
constexpr ParamDefault text(const char* value)
{
  return ParamDefault{ 0.0, value, "" };
}
constexpr ParamDefault unset(const char* meaning)
{
  return ParamDefault{ 0.0, "", meaning };
}

std::vector<std::string> splitNames(const std::string& names)
{
  std::vector<std::string> split;
  std::istringstream in(names);
  std::string name;
  while (in >> name)
    split.push_back(name);
  return split;
}

// A pipeline row's default: a value, or automatic (kAutomatic and what it follows).
struct PipelineDefault
{
  PipelineDefault(double v) : value(v), automatic("") {}  // NOLINT: rows write plain numbers
  PipelineDefault(AutomaticDefault a) : value(kAutomatic), automatic(a.meaning) {}  // NOLINT
  double value;
  const char* automatic;
};

ParamInfo pipelineRow(const char* field, double Params::*real_field, int Params::*integer_field,
                      PipelineDefault default_value, const char* name, const char* symbol, const char* aliases,
                      const char* label, ParamBound lower, ParamBound upper, const char* greater_than,
                      const char* unit, const char* doc)
{
  return ParamInfo{ name,
                    symbol,
                    splitNames(aliases),
                    label,
                    real_field != nullptr ? ParamType::real : ParamType::integer,
                    ParamScope::pipeline,
                    true,
                    number(default_value.value),
                    lower,
                    upper,
                    greater_than,
                    unit,
                    doc,
                    "",
                    "Params::validate (core/params.h)",
                    nullptr,
                    field,
                    real_field,
                    integer_field,
                    default_value.automatic };
}

ParamInfo pipelineRow(const char* field, double Params::*real_field, PipelineDefault default_value, const char* name,
                      const char* symbol, const char* aliases, const char* label, ParamBound lower, ParamBound upper,
                      const char* greater_than, const char* unit, const char* doc)
{
  return pipelineRow(field, real_field, nullptr, default_value, name, symbol, aliases, label, lower, upper,
                     greater_than, unit, doc);
}

ParamInfo pipelineRow(const char* field, int Params::*integer_field, PipelineDefault default_value, const char* name,
                      const char* symbol, const char* aliases, const char* label, ParamBound lower, ParamBound upper,
                      const char* greater_than, const char* unit, const char* doc)
{
  return pipelineRow(field, nullptr, integer_field, default_value, name, symbol, aliases, label, lower, upper,
                     greater_than, unit, doc);
}

ParamInfo startUpRow(ParamScope scope, ParamType type, const char* name, const char* aliases,
                     ParamDefault default_value, ParamBound lower, ParamBound upper, const char* unit, const char* doc,
                     const char* allowed, const char* checked_by, std::string (*check)(double))
{
  return ParamInfo{ name,  "",    splitNames(aliases), name,    type,       scope, false, default_value,
                    lower, upper, "",                  unit,    doc,        allowed, checked_by,
                    check, "",    nullptr,             nullptr, "" };
}

// The names users see: the ROS parameter name (original launch file) and its label.
std::string describe(const ParamInfo& param, double value)
{
  std::ostringstream out;
  out << param.name << " (" << param.label << ") = " << value;
  return out.str();
}

// A bound as people write it ("0", "0.5"), not std::to_string's "0.000000".
std::string bound(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

bool satisfies(double value, const ParamBound& lower, const ParamBound& upper)
{
  const bool above_lower = !lower.present || (lower.inclusive ? value >= lower.value : value > lower.value);
  const bool below_upper = !upper.present || (upper.inclusive ? value <= upper.value : value < upper.value);
  return above_lower && below_upper;
}

// Appends what is wrong with `value` of `param`: non-finite or below the lower bound, above
// the upper bound, or not above the parameter it must exceed.
void checkValue(const ParamInfo& param, double value, const Params& params, std::vector<std::string>& errors)
{
  if (param.isAutomatic(params))
    return;
  // The range of an automatic parameter's own values, and the value that leaves it to the sensor.
  const std::string unit = std::string(" ") + param.unit + (*param.automatic != '\0' ? ", or 0: automatic" : "");
  if (!std::isfinite(value) || !satisfies(value, param.lower, ParamBound()))
  {
    if (param.lower.present)
      errors.push_back(describe(param, value) + " is out of range: must be finite and " +
                       (param.lower.inclusive ? ">= " : "> ") + bound(param.lower.value) + unit);
    else
      errors.push_back(describe(param, value) + " is out of range: must be finite");
  }
  else if (!satisfies(value, ParamBound(), param.upper))
  {
    const std::string upper_end = bound(param.upper.value) + (param.upper.inclusive ? "]" : ")");
    if (param.lower.present)
      errors.push_back(describe(param, value) + " is out of range: must be in " +
                       (param.lower.inclusive ? "[" : "(") + bound(param.lower.value) + ", " + upper_end);
    else
      errors.push_back(describe(param, value) + " is out of range: must be " +
                       (param.upper.inclusive ? "<= " : "< ") + bound(param.upper.value) + unit);
  }
  if (*param.above == '\0')
    return;
  const ParamInfo& smaller = *findParameter(param.above);
  const double smaller_value = smaller.value(params);
  if (std::isfinite(value) && std::isfinite(smaller_value) && !(smaller_value < value))
    errors.push_back(describe(smaller, smaller_value) + " must be smaller than " + param.name + " (" + param.label +
                     ") = " + bound(value));
}
}  // namespace

const char* paramTypeName(ParamType type)
{
  switch (type)
  {
    case ParamType::real: return "real";
    case ParamType::integer: return "integer";
    case ParamType::text: return "text";
    case ParamType::real_list: return "real_list";
  }
  return "?";
}

const char* paramScopeName(ParamScope scope)
{
  switch (scope)
  {
    case ParamScope::pipeline: return "pipeline";
    case ParamScope::core_input: return "core_input";
    case ParamScope::ros_input: return "ros_input";
    case ParamScope::node: return "node";
  }
  return "?";
}

std::vector<std::string> ParamInfo::names() const
{
  std::vector<std::string> all{ name };
  if (*symbol != '\0')
    all.emplace_back(symbol);
  all.insert(all.end(), aliases.begin(), aliases.end());
  return all;
}

double ParamInfo::value(const Params& params) const
{
  return real_field != nullptr ? params.*real_field : static_cast<double>(params.*integer_field);
}

bool ParamInfo::isAutomatic(const Params& params) const
{
  return *automatic != '\0' && value(params) == kAutomatic;
}

const std::vector<ParamInfo>& parameterTable()
{
  static const std::vector<ParamInfo> table = {
#define OHM_PIPELINE_PARAMETER(field, type, default_value, name, symbol, aliases, label, lower, upper, greater_than, \
                               unit, doc)                                                                         \
  pipelineRow(#field, &Params::field, default_value, name, symbol, aliases, label, lower, upper, greater_than, unit, \
              doc),
#define OHM_START_UP_PARAMETER(scope, type, name, aliases, default_value, lower, upper, unit, doc, allowed, \
                               checked_by, check)                                                         \
  startUpRow(scope, type, name, aliases, default_value, lower, upper, unit, doc, allowed, checked_by, check),
#include "ohm_mirror_detector3d/core/parameters.def"
#undef OHM_PIPELINE_PARAMETER
#undef OHM_START_UP_PARAMETER
  };
  return table;
}

const ParamInfo* findParameter(const std::string& name)
{
  for (const ParamInfo& param : parameterTable())
    for (const std::string& accepted : param.names())
      if (accepted == name)
        return &param;
  return nullptr;
}

std::vector<std::string> Params::validate() const
{
  std::vector<std::string> errors;
  for (const ParamInfo& param : parameterTable())
    if (param.scope == ParamScope::pipeline)
      checkValue(param, param.value(*this), *this, errors);
  return errors;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
