#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/param_table.h"

namespace ohm_mirror_detector3d
{
namespace
{
using core::ParamInfo;
using core::ParamScope;
using core::ParamType;

bool mentions(const std::vector<std::string>& errors, const std::string& text)
{
  for (const std::string& error : errors)
    if (error.find(text) != std::string::npos)
      return true;
  return false;
}

// Params with one pipeline parameter set to `value` (rounded for an integer parameter), and a
// parameter it must exceed at its own least value.
core::Params withValue(const ParamInfo& param, double value)
{
  core::Params params;
  if (*param.above != '\0')
  {
    const ParamInfo& smaller = *core::findParameter(param.above);
    params.*smaller.real_field = smaller.lower.value;
  }
  if (param.real_field != nullptr)
    params.*param.real_field = value;
  else
    params.*param.integer_field = static_cast<int>(value);
  return params;
}

TEST(ParamTable, EveryNameSymbolAndAliasNamesOneParameter)
{
  std::set<std::string> seen;
  for (const ParamInfo& param : core::parameterTable())
    for (const std::string& name : param.names())
    {
      EXPECT_TRUE(seen.insert(name).second) << name << " is given to two parameters";
      ASSERT_NE(core::findParameter(name), nullptr) << name;
      EXPECT_STREQ(core::findParameter(name)->name, param.name) << name;
    }
  EXPECT_EQ(core::findParameter("outlier_radius"), nullptr);  // a C++ field name is no parameter name
  EXPECT_EQ(core::findParameter(""), nullptr);
}

TEST(ParamTable, PipelineRowsAreTheFieldsOfParamsWithTheirDefaults)
{
  const core::Params defaults;
  std::size_t pipeline_rows = 0;
  for (const ParamInfo& param : core::parameterTable())
  {
    if (param.scope != ParamScope::pipeline)
      continue;
    ++pipeline_rows;
    SCOPED_TRACE(param.name);
    EXPECT_TRUE(param.reconfigurable);
    EXPECT_NE(std::string(param.field), "");
    ASSERT_NE((param.real_field != nullptr), (param.integer_field != nullptr));
    EXPECT_EQ(param.type, param.real_field != nullptr ? ParamType::real : ParamType::integer);
    EXPECT_EQ(param.value(defaults), param.default_value.number);
    EXPECT_NE(std::string(param.doc), "");
    EXPECT_NE(std::string(param.label), "");
    EXPECT_TRUE(param.lower.present) << "every pipeline parameter has a lower bound";
  }
  EXPECT_EQ(pipeline_rows, 37u);
  EXPECT_TRUE(defaults.validate().empty());
}

TEST(ParamTable, PipelineParametersComeFirst)
{
  bool start_up_seen = false;
  for (const ParamInfo& param : core::parameterTable())
  {
    if (param.scope != ParamScope::pipeline)
      start_up_seen = true;
    else
      EXPECT_FALSE(start_up_seen) << param.name << " comes after a start-up parameter";
  }
}

TEST(ParamTable, ValidateRefusesEveryValueJustOutsideTheTablesRangeAndAcceptsItsBounds)
{
  for (const ParamInfo& param : core::parameterTable())
  {
    if (param.scope != ParamScope::pipeline)
      continue;
    SCOPED_TRACE(param.name);
    const std::string named = std::string(param.name) + " (" + param.label + ") = ";
    const double step = param.type == ParamType::integer ? 1.0 : 1e-6;
    const double lower = param.lower.value;
    // An inclusive bound is allowed, the value one step beyond it is not; an exclusive bound
    // is refused itself.
    EXPECT_EQ(withValue(param, param.lower.inclusive ? lower : lower + step).validate().empty(), true);
    double refused = param.lower.inclusive ? lower - step : lower;
    // 0 of a parameter that follows the sensor is "not set", no value out of range.
    if (*param.automatic != '\0' && refused == core::kAutomatic)
    {
      EXPECT_TRUE(withValue(param, core::kAutomatic).validate().empty());
      refused -= step;
    }
    const std::vector<std::string> below = withValue(param, refused).validate();
    EXPECT_TRUE(mentions(below, named)) << (below.empty() ? "accepted" : below.front());
    EXPECT_TRUE(mentions(below, "is out of range: must be finite and " +
                                    std::string(param.lower.inclusive ? ">= " : "> ")));
    if (param.real_field != nullptr)
    {
      EXPECT_TRUE(mentions(withValue(param, std::numeric_limits<double>::quiet_NaN()).validate(), named + "nan"));
      if (!param.upper.present && *param.above == '\0')
      {
        EXPECT_TRUE(mentions(withValue(param, std::numeric_limits<double>::infinity()).validate(), named + "inf"));
      }
    }
    if (param.upper.present)
    {
      const double upper = param.upper.value;
      EXPECT_TRUE(withValue(param, param.upper.inclusive ? upper : upper - step).validate().empty());
      const std::vector<std::string> above = withValue(param, param.upper.inclusive ? upper + step : upper).validate();
      EXPECT_TRUE(mentions(above, named) && mentions(above, "is out of range: must be in "));
    }
  }
}

TEST(ParamTable, AParameterThatMustExceedAnotherIsCheckedAgainstIt)
{
  for (const ParamInfo& param : core::parameterTable())
  {
    if (*param.above == '\0')
      continue;
    SCOPED_TRACE(param.name);
    const ParamInfo* smaller = core::findParameter(param.above);
    ASSERT_NE(smaller, nullptr);
    ASSERT_EQ(smaller->scope, ParamScope::pipeline);
    core::Params params;
    params.*smaller->real_field = 5.0;
    params.*param.real_field = 5.0;
    EXPECT_TRUE(mentions(params.validate(), std::string(smaller->name) + " (" + smaller->label +
                                                ") = 5 must be smaller than " + param.name));
    params.*param.real_field = 5.5;
    EXPECT_TRUE(params.validate().empty());
  }
}

TEST(ParamTable, StartUpRowsAreNotPipelineFieldsAndAreNotReconfigurable)
{
  std::set<std::string> names;
  for (const ParamInfo& param : core::parameterTable())
  {
    if (param.scope == ParamScope::pipeline)
      continue;
    SCOPED_TRACE(param.name);
    names.insert(param.name);
    EXPECT_FALSE(param.reconfigurable);
    EXPECT_EQ(param.real_field, nullptr);
    EXPECT_EQ(param.integer_field, nullptr);
    EXPECT_NE(std::string(param.checked_by), "");
    EXPECT_NE(std::string(param.doc), "");
    // Only a core input can be checked by the core.
    EXPECT_TRUE(param.check == nullptr || param.scope == ParamScope::core_input);
    // Numbers say their range by bounds, everything else in words.
    const bool numeric = param.type == ParamType::real || param.type == ParamType::integer;
    EXPECT_EQ(std::string(param.allowed).empty(), numeric);
    if (param.type == ParamType::text && *param.default_value.text == '\0')
    {
      EXPECT_NE(std::string(param.default_value.when_unset), "") << "an empty default says what it means";
    }
  }
  for (const char* name : { "input_mode", "azimuth_resolution_deg", "sensor_frame", "sweep_frame", "sweep_period",
                            "rotation_axis", "approximate_sync", "sub_input_scan", "pub_labelled", "pub_cleaned",
                            "pub_objects", "pub_markers", "diagnostic_period" })
    EXPECT_EQ(names.count(name), 1u) << name;
  // The original's output names are rows of their own, with the original's meaning: pub_scan is
  // its prefiltered scan, no other name of ~cleaned.
  for (const char* name : { "pub_scan", "pub_object", "pub_transp", "pub_mirror", "pub_affected", "pub_behTransp",
                            "pub_behMirror", "pub_backprojMirror", "pub_cleaned", "pub_marker" })
  {
    ASSERT_NE(core::findParameter(name), nullptr) << name;
    EXPECT_STREQ(core::findParameter(name)->name, name);
    EXPECT_TRUE(core::findParameter(name)->aliases.empty()) << name;
  }
}

TEST(ParamTable, TheAzimuthResolutionRowIsWhatItsCheckAccepts)
{
  const ParamInfo& param = *core::findParameter("azimuth_resolution_deg");
  EXPECT_EQ(param.scope, ParamScope::core_input);
  // Not given: worked out from each cloud, which the check accepts as the value 0.
  EXPECT_EQ(param.default_value.number, core::kAzimuthStepFromCloud);
  EXPECT_STRNE(param.default_value.when_unset, "");
  ASSERT_TRUE(param.lower.present && param.lower.inclusive && param.upper.present && param.upper.inclusive);
  ASSERT_EQ(param.check, &core::validateAzimuthResolution);
  EXPECT_EQ(param.check(param.lower.value), "");
  EXPECT_EQ(param.check(param.upper.value), "");
  EXPECT_EQ(param.check(param.default_value.number), "");
  EXPECT_NE(param.check(std::nextafter(param.lower.value, 0.0)), "");
  EXPECT_NE(param.check(std::nextafter(param.upper.value, 100.0)), "");
}

}  // namespace
}  // namespace ohm_mirror_detector3d
