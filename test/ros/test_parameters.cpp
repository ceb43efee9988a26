// The ROS side of the parameter table: cfg/PreFilter.cfg (as dynamic_reconfigure generated it),
// fromConfig and readParams agree with core/param_table.h, and so do the start-up readers'
// defaults. (The cfg file's descriptions are checked against the table by
// test/python/test_parameter_docs.py.)
#include <gtest/gtest.h>

#include <boost/any.hpp>
#include <dynamic_reconfigure/Config.h>

#include <climits>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/ros/dual_return.h"
#include "ohm_mirror_detector3d/core/legacy_values.h"
#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace
{
using Description = PreFilterConfig::AbstractParamDescriptionConstPtr;

double numberOf(const Description& description, const PreFilterConfig& config)
{
  boost::any value;
  description->getValue(config, value);
  return description->type == "double" ? boost::any_cast<double>(value) : boost::any_cast<int>(value);
}

std::vector<const core::ParamInfo*> reconfigurableRows()
{
  std::vector<const core::ParamInfo*> rows;
  for (const core::ParamInfo& param : core::parameterTable())
    if (param.reconfigurable)
      rows.push_back(&param);
  return rows;
}

TEST(Parameters, TheReconfigureConfigHoldsTheTablesReconfigurableRowsWithTheirTypesAndDefaultsUnclamped)
{
  const std::vector<Description>& descriptions = PreFilterConfig::__getParamDescriptions__();
  const std::vector<const core::ParamInfo*> rows = reconfigurableRows();
  ASSERT_EQ(descriptions.size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    const core::ParamInfo& param = *rows[k];
    const Description& description = descriptions[k];
    SCOPED_TRACE(param.name);
    EXPECT_EQ(description->name, param.name) << "in the table's order";
    EXPECT_EQ(description->type, param.type == core::ParamType::real ? "double" : "int");
    EXPECT_EQ(numberOf(description, PreFilterConfig::__getDefault__()), param.default_value.number);
    // No min/max: dynamic_reconfigure would clamp silently where the pre-filter refuses.
    if (param.type == core::ParamType::real)
    {
      EXPECT_EQ(numberOf(description, PreFilterConfig::__getMin__()), -std::numeric_limits<double>::infinity());
      EXPECT_EQ(numberOf(description, PreFilterConfig::__getMax__()), std::numeric_limits<double>::infinity());
    }
    else
    {
      EXPECT_EQ(numberOf(description, PreFilterConfig::__getMin__()), INT_MIN);
      EXPECT_EQ(numberOf(description, PreFilterConfig::__getMax__()), INT_MAX);
    }
  }
}

TEST(Parameters, FromConfigSetsEveryParameterFromItsOwnField)
{
  dynamic_reconfigure::Config message;
  int k = 1;
  for (const core::ParamInfo* param : reconfigurableRows())
  {
    if (param->type == core::ParamType::real)
    {
      dynamic_reconfigure::DoubleParameter value;
      value.name = param->name;
      value.value = 0.5 + k;
      message.doubles.push_back(value);
    }
    else
    {
      dynamic_reconfigure::IntParameter value;
      value.name = param->name;
      value.value = 1000 + k;
      message.ints.push_back(value);
    }
    ++k;
  }
  PreFilterConfig config = PreFilterConfig::__getDefault__();
  ASSERT_TRUE(config.__fromMessage__(message));
  const core::Params params = ros_io::fromConfig(config);
  k = 1;
  for (const core::ParamInfo* param : reconfigurableRows())
  {
    EXPECT_EQ(param->value(params), param->type == core::ParamType::real ? 0.5 + k : 1000 + k) << param->name;
    ++k;
  }
}

// Parameters as a map of names to numbers (integers stay integers, as on the parameter server).
class MapParams : public ros_io::ParamSource
{
public:
  std::map<std::string, double> numbers;
  std::set<std::string> integers;

  bool has(const std::string& name) const override { return numbers.count(name) > 0; }
  bool get(const std::string& name, double& value) const override
  {
    if (!has(name))
      return false;
    value = numbers.at(name);
    return true;
  }
  bool get(const std::string& name, int& value) const override
  {
    if (integers.count(name) == 0)
      return false;
    value = static_cast<int>(numbers.at(name));
    return true;
  }
  bool get(const std::string&, std::string&) const override { return false; }
  bool get(const std::string&, std::vector<double>&) const override { return false; }
  std::string describe(const std::string& name) const override { return "~" + name; }
};

TEST(Parameters, ReadParamsTakesEveryNameTheTableAcceptsAndRefusesDisagreeingOnes)
{
  for (const core::ParamInfo* param : reconfigurableRows())
  {
    for (const std::string& name : param->names())
    {
      SCOPED_TRACE(name);
      MapParams source;
      source.numbers[name] = param->type == core::ParamType::real ? 7.25 : 7.0;
      if (param->type == core::ParamType::integer)
        source.integers.insert(name);
      std::vector<std::string> errors;
      const core::Params params = ros_io::readParams(source, errors);
      EXPECT_TRUE(errors.empty());
      EXPECT_EQ(param->value(params), source.numbers[name]);
    }
    const std::vector<std::string> names = param->names();
    if (names.size() < 2)
      continue;
    MapParams source;
    source.numbers[names[0]] = 3.0;
    source.numbers[names[1]] = 4.0;
    source.integers = { names[0], names[1] };
    std::vector<std::string> errors;
    ros_io::readParams(source, errors);
    ASSERT_EQ(errors.size(), 1u) << param->name;
    EXPECT_NE(errors[0].find("name the same value and disagree"), std::string::npos) << errors[0];
  }
  MapParams source;
  source.numbers["n_inlier"] = 5.5;  // not an integer
  std::vector<std::string> errors;
  ros_io::readParams(source, errors);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "parameter ~n_inlier has the wrong type: expected an integer");
}

TEST(Parameters, TheStartUpReadersDefaultsAreTheTables)
{
  const MapParams none;
  std::vector<std::string> errors;
  EXPECT_EQ(ros_io::readAzimuthResolution(none, errors), core::findParameter("azimuth_resolution_deg")->default_value.number);
  const ros_io::MultiEchoScanOptions scan_options;
  EXPECT_EQ(scan_options.sweep_period, core::findParameter("sweep_period")->default_value.number);
  EXPECT_STREQ(core::findParameter("rotation_axis")->default_value.text, "[0, 0, 1]");
  EXPECT_EQ(scan_options.rotation_axis, Eigen::Vector3d::UnitZ());
  // sweep_period's lower bound is where its reader starts refusing.
  MapParams negative;
  negative.numbers["sweep_frame"] = 0.0;
  negative.numbers["sweep_period"] = std::nextafter(core::findParameter("sweep_period")->lower.value, -1.0);
  errors.clear();
  ros_io::readMultiEchoScanOptions(negative, errors);
  bool refused = false;
  for (const std::string& error : errors)
    refused = refused || error.find("sweep_period") != std::string::npos;
  EXPECT_TRUE(refused);
}

TEST(Parameters, ARecordingSourceKnowsWhatWasAskedFor)
{
  MapParams values;
  values.numbers["r"] = 0.2;
  values.numbers["typo"] = 1.0;
  const ros_io::RecordingParamSource source(values);
  std::vector<std::string> errors;
  const core::Params params = ros_io::readParams(source, errors);
  EXPECT_EQ(params.outlier_radius, 0.2);
  EXPECT_TRUE(source.wasAsked("r"));
  EXPECT_TRUE(source.wasAsked("outlierFilter_searchRadius"));
  EXPECT_FALSE(source.wasAsked("typo"));
  EXPECT_FALSE(source.wasAsked("diagnostic_period"));
  source.markUsed("diagnostic_period");
  EXPECT_TRUE(source.wasAsked("diagnostic_period"));
}

TEST(Parameters, EveryUnusedNameGetsOneWarningSayingWhatItIs)
{
  const MapParams source;
  const std::vector<std::string> warnings = ros_io::unusedParameterWarnings(
      { "sweep_frame", "outlierFilter_minNeighbours", "source_frame" }, source, "input_mode pair");
  ASSERT_EQ(warnings.size(), 3u);
  // A parameter of the table that this mode does not read: what it is for.
  EXPECT_EQ(warnings[0], "parameter ~sweep_frame is not used with input_mode pair and is ignored (it is: " +
                             std::string(core::findParameter("sweep_frame")->doc) + ")");
  // A typo: the name it is nearest to.
  EXPECT_EQ(warnings[1], "parameter ~outlierFilter_minNeighbours is no parameter of the pre-filter and is ignored "
                         "(did you mean outlierFilter_minNeighbors?)");
  // A name of the original node that means nothing here.
  EXPECT_EQ(warnings[2], "parameter ~source_frame is no parameter of the pre-filter and is ignored (a typo, or a "
                         "name of the original node that has no meaning here)");
  EXPECT_TRUE(ros_io::unusedParameterWarnings({}, source, "input_mode pair").empty());
}

TEST(Parameters, ARefusedReconfigureNamesTheValuesKeptAndOnlyThose)
{
  PreFilterConfig kept = PreFilterConfig::__getDefault__();
  kept.outlierFilter_searchRadius = 0.2;
  PreFilterConfig refused = kept;
  refused.outlierFilter_searchRadius = -1.0;
  refused.planeDetection_minAmountPoints = 2;
  const std::vector<std::string> lines = ros_io::keptValues(kept, refused);
  EXPECT_EQ(lines, (std::vector<std::string>{ "outlierFilter_searchRadius = 0.2 (not -1)",
                                              // the default: 0, automatic (follows the sensor)
                                              "planeDetection_minAmountPoints = 0 (not 2)" }));
  EXPECT_TRUE(ros_io::keptValues(kept, kept).empty());
}

// The pipeline parameters `source` gives, with the legacy values mapped, and the log lines.
core::Params readMapped(const MapParams& source, std::vector<std::string>& lines)
{
  std::vector<std::string> errors;
  core::Params params = ros_io::readParams(source, errors);
  EXPECT_TRUE(errors.empty());
  lines = core::mapLegacyValues([&](const std::string& name) { return source.has(name); }, params);
  return params;
}

MapParams originalLaunchValues()
{
  MapParams source;
  source.numbers = { { "outlierFilter_minNeighbors", 50 },      { "outlierFilter_searchRadius", 0.1 },
                     { "substract_threshold_distance", 0.05 }, { "max_Dist_ICP", 0.01 },
                     { "fitness_Fct_ICP", 0.005 },             { "planeDetection_minAmountPoints", 100 } };
  source.integers = { "outlierFilter_minNeighbors", "planeDetection_minAmountPoints" };
  return source;
}

TEST(LegacyValues, TheOriginalsValuesUnderItsNamesAreMappedToWhatTheyMeantOneLineEach)
{
  std::vector<std::string> lines;
  const core::Params params = readMapped(originalLaunchValues(), lines);
  EXPECT_EQ(params.outlier_min_neighbors, 0);  // automatic: the sweep's own beam grid
  EXPECT_EQ(params.outlier_radius, core::kAutomatic);
  EXPECT_DOUBLE_EQ(params.icp_max_distance, 0.1);  // at least the default landing tolerance
  EXPECT_EQ(params.min_object_points, 100);          // means here what it meant there
  EXPECT_DOUBLE_EQ(params.icp_fitness_threshold, 0.005);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("outlierFilter_minNeighbors 50 within outlierFilter_searchRadius 0.1 m"), std::string::npos)
      << lines[0];
  EXPECT_NE(lines[0].find("read as automatic"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("max_Dist_ICP 0.01 m"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("the default 0.1 m"), std::string::npos) << lines[1];
}

TEST(LegacyValues, TheNewNamesAreHonouredAsSet)
{
  MapParams source;
  source.numbers = { { "n_inlier", 50 }, { "r", 0.1 }, { "icp_max_distance", 0.01 } };
  source.integers = { "n_inlier" };
  std::vector<std::string> lines;
  const core::Params params = readMapped(source, lines);
  EXPECT_EQ(params.outlier_min_neighbors, 50);
  EXPECT_DOUBLE_EQ(params.outlier_radius, 0.1);
  EXPECT_DOUBLE_EQ(params.icp_max_distance, 0.01);
  EXPECT_TRUE(lines.empty());

  // A legacy name given beside its new name with the same value: the new name's meaning.
  MapParams both = originalLaunchValues();
  both.numbers["icp_max_distance"] = 0.01;
  both.numbers["n_inlier"] = 50;
  both.integers.insert("n_inlier");
  const core::Params kept = readMapped(both, lines);
  EXPECT_DOUBLE_EQ(kept.icp_max_distance, 0.01);
  EXPECT_EQ(kept.outlier_min_neighbors, 50);
  EXPECT_DOUBLE_EQ(kept.outlier_radius, 0.1);
  EXPECT_TRUE(lines.empty());
}

TEST(LegacyValues, ValuesThatMeanTheSameHereAreTakenAsTheyAre)
{
  // One neighbour within a radius is no density (the tests' "filter nothing": 1 within 100 m);
  // a tolerance of at least d_thres is one here too; the radius alone is a sphere as set.
  MapParams source;
  source.numbers = { { "outlierFilter_minNeighbors", 1 }, { "outlierFilter_searchRadius", 100.0 },
                     { "max_Dist_ICP", 0.1 } };
  source.integers = { "outlierFilter_minNeighbors" };
  std::vector<std::string> lines;
  core::Params params = readMapped(source, lines);
  EXPECT_EQ(params.outlier_min_neighbors, 1);
  EXPECT_DOUBLE_EQ(params.outlier_radius, 100.0);
  EXPECT_DOUBLE_EQ(params.icp_max_distance, 0.1);
  EXPECT_TRUE(lines.empty());

  MapParams radius_only;
  radius_only.numbers = { { "outlierFilter_searchRadius", 0.1 } };
  params = readMapped(radius_only, lines);
  EXPECT_DOUBLE_EQ(params.outlier_radius, 0.1);
  EXPECT_TRUE(lines.empty());
}

}  // namespace
}  // namespace ohm_mirror_detector3d
