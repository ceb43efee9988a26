// prefilter_bag IN.bag OUT.bag: the pre-filter over a bag, no master needed. The command
// line only; the work is runPrefilterBag (bag_processor.h).
#include <csignal>
#include <cstring>
#include <exception>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/ros/bag_processor.h"
#include "ohm_mirror_detector3d/ros/input_mode.h"
#include "ohm_mirror_detector3d/core/legacy_values.h"
#include "ohm_mirror_detector3d/ros/parameters.h"
#include "ohm_mirror_detector3d/ros/yaml_params.h"

namespace
{
using namespace ohm_mirror_detector3d;

// Exit codes.
constexpr int kExitFailure = 1;      // the bag could not be processed
constexpr int kExitUsage = 2;        // bad command line or parameters
constexpr int kExitInterrupted = 130;

volatile std::sig_atomic_t g_stop = 0;

void onSignal(int /*signal*/)
{
  g_stop = 1;
}

void printHelp(std::ostream& out)
{
  out << "Usage: prefilter_bag IN.bag OUT.bag [options]\n"
         "\n"
         "Runs the pre-filter (the nodelet's pipeline, the same code) over every input sweep of IN.bag,\n"
         "as fast as the CPU allows and without a ROS master, and writes OUT.bag with the outputs\n"
         "PREFIX/labelled, PREFIX/cleaned (sensor_msgs/PointCloud2), PREFIX/objects\n"
         "(ohm_mirror_detector3d/ReflectiveObjectArray) and PREFIX/markers (visualization_msgs/MarkerArray),\n"
         "stamped and framed like their input, at the bag time of their input message (in two_topics mode:\n"
         "of the later cloud of the pair; in multi_echo_scan mode: stamped and framed like the assembled\n"
         "sweep, at the bag time of the scan or tf message that completed it; with sensor_frame: at the\n"
         "bag time of the message after which tf had the scanner's pose). Every other message of\n"
         "IN.bag, the input topics included, is copied unchanged at its own bag time, unless\n"
         "--only-outputs. Messages already on the output topics in IN.bag are not copied: the new\n"
         "outputs replace them.\n"
         "\n"
         "Options:\n"
         "  --input-mode MODE    how sweeps are read; by default the type on --input-topic in the bag\n"
         "                       chooses it, as for the nodelet without input_mode: "
      << ros_io::runTimeInputMode().help << ". The modes:\n";
  for (const ros_io::InputMode& mode : ros_io::inputModes())
    out << "                         " << mode.name << ": " << mode.help << "\n";
  out << "  --input-topic T      the input topic of every mode but two_topics; by default what\n"
         "                       synthesize_sweep --bag writes (without --input-mode: the first of\n"
         "                       these the bag has, of the modes it may choose):\n";
  for (const ros_io::InputMode& mode : ros_io::inputModes())
    if (mode.default_topic != nullptr)
      out << "                         " << mode.name << ": " << mode.default_topic << "\n";
  out << "  --echo1-topic T      two_topics: the first echo (default /echo1)\n"
         "  --echo2-topic T      two_topics: the second echo (default /echo2)\n"
         "  --params FILE.yaml   pre-filter parameters, as for the nodelet: the original launch file's names\n"
         "                       (outlierFilter_searchRadius, ...) or the paper's symbols (r, ...), e.g.\n"
         "                       launch/rotating_hokuyo_params.yaml; its input_mode is used unless\n"
         "                       --input-mode is given. Bad values are refused with the nodelet's messages.\n"
         "                       Also the modes' start-up parameters, as for the nodelet: dual_return:\n"
         "                       azimuth_resolution_deg (default 360/2048); two_topics: approximate_sync\n"
         "                       (default 0: equal stamps; > 0: stamps at most that many seconds apart);\n"
         "                       multi_echo_scan: sweep_frame\n"
         "                       (required), sweep_period (default 0: per half rotation), rotation_axis\n"
         "                       (default [0, 0, 1]); every mode but multi_echo_scan: sensor_frame (the\n"
         "                       scanner's frame when the clouds come in another). multi_echo_scan and\n"
         "                       sensor_frame take tf from the bag's /tf and /tf_static, in bag order.\n"
         "  --only-outputs       write only the four outputs, copy nothing else\n"
         "  --prefix NS          namespace of the outputs (default /prefilter)\n"
         "  -v, --verbose        a timing line per sweep, every dropped input\n"
         "  -h, --help           this text\n"
         "\n"
         "Progress and a summary (sweeps processed and dropped, objects by type, per-sweep time median and\n"
         "p95, wall time) go to stderr. An input message that makes no sweep (e.g. echoes of different\n"
         "sizes) is reported and counted, not fatal. OUT.bag is written as OUT.bag.partial and renamed when\n"
         "complete; on an error or Ctrl-C the partial file is removed. OUT.bag is overwritten if it exists.\n"
         "\n"
         "Exit status: 0 done, 1 the bag could not be processed (unreadable, missing topic, wrong type),\n"
         "2 bad command line or parameters, 130 interrupted.\n";
}

struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

// No --params: every parameter keeps its default (a required one is reported missing).
class NoParams : public ros_io::ParamSource
{
public:
  bool has(const std::string& /*name*/) const override { return false; }
  bool get(const std::string& /*name*/, double& /*value*/) const override { return false; }
  bool get(const std::string& /*name*/, int& /*value*/) const override { return false; }
  bool get(const std::string& /*name*/, std::string& /*value*/) const override { return false; }
  bool get(const std::string& /*name*/, std::vector<double>& /*value*/) const override { return false; }
  std::string describe(const std::string& name) const override { return name + " (give it in a --params file)"; }
};

std::string joinLines(const std::vector<std::string>& lines)
{
  std::string joined;
  for (const std::string& line : lines)
    joined += "\n  " + line;
  return joined;
}

// "pair", or without --input-mode the modes the bag's type may choose: "pair or hokuyo3d_legacy (...)".
std::string modeNames(const std::string& input_mode)
{
  if (!input_mode.empty())
    return input_mode;
  std::string names;
  for (const ros_io::InputMode* mode : ros_io::runTimeChoices())
    names += (names.empty() ? "" : " or ") + std::string(mode->name);
  return names + " (which the bag's type chooses when --input-mode is not given)";
}

// Parses argv into `options`; returns false when --help was given.
bool parseCommandLine(int argc, char** argv, ros_io::BagToolOptions& options)
{
  const std::set<std::string> with_value = { "--input-mode", "--input-topic", "--echo1-topic",
                                             "--echo2-topic", "--params", "--prefix" };
  std::map<std::string, std::string> given;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i)
  {
    std::string arg = argv[i];
    if (arg == "-h" || arg == "--help")
      return false;
    if (arg == "--only-outputs")
      options.only_outputs = true;
    else if (arg == "-v" || arg == "--verbose")
      options.verbose = true;
    else if (arg.size() > 2 && arg.compare(0, 2, "--") == 0)
    {
      std::string value;
      const std::size_t equals = arg.find('=');
      if (equals != std::string::npos)
      {
        value = arg.substr(equals + 1);
        arg = arg.substr(0, equals);
      }
      else if (with_value.count(arg) > 0)
      {
        if (i + 1 >= argc)
          throw UsageError(arg + " needs a value");
        value = argv[++i];
      }
      if (with_value.count(arg) == 0)
        throw UsageError("unknown option " + arg);
      if (value.empty())
        throw UsageError(arg + " needs a non-empty value");
      given[arg] = value;
    }
    else if (arg.size() > 1 && arg[0] == '-')
      throw UsageError("unknown option " + arg);
    else
      positional.push_back(arg);
  }
  if (positional.size() != 2)
    throw UsageError("expected IN.bag and OUT.bag, got " + std::to_string(positional.size()) + " file name(s)");
  options.input_path = positional[0];
  options.output_path = positional[1];

  // Parameters first: the file may name the input mode.
  std::unique_ptr<ros_io::YamlParamFile> file;
  const std::string params_path = given.count("--params") > 0 ? given["--params"] : "";
  std::vector<std::string> errors;
  std::string file_input_mode;
  std::vector<std::string> legacy_mappings;
  if (!params_path.empty())
  {
    try
    {
      file.reset(new ros_io::YamlParamFile(params_path));
    }
    catch (const std::runtime_error& e)
    {
      throw UsageError(e.what());
    }
    options.params = ros_io::readParams(*file, errors);
    const std::vector<std::string> range_errors = options.params.validate();
    errors.insert(errors.end(), range_errors.begin(), range_errors.end());
    // Values that are refused are refused as given, not mapped.
    if (errors.empty())
      legacy_mappings =
          core::mapLegacyValues([&](const std::string& name) { return file->has(name); }, options.params);
    if (file->has("input_mode") && !file->get("input_mode", file_input_mode))
      errors.push_back("parameter " + file->describe("input_mode") + " has the wrong type: expected a string");
  }
  if (given.count("--input-mode") > 0)
    options.input_mode = given["--input-mode"];
  else if (!file_input_mode.empty())
    options.input_mode = file_input_mode;
  const ros_io::InputMode* mode =
      options.input_mode.empty() ? &ros_io::runTimeInputMode() : ros_io::findInputMode(options.input_mode);
  if (mode == nullptr)
    throw UsageError(ros_io::unknownInputModeMessage(options.input_mode));
  // The start-up parameters of the input modes, read as the nodelet reads them.
  const NoParams no_params;
  const ros_io::ParamSource& source = file ? static_cast<const ros_io::ParamSource&>(*file) : no_params;
  ros_io::readInputOptions(source, *mode, options.input, errors);
  options.input.log_name = "prefilter_bag";
  if (!errors.empty())
    throw UsageError("refusing to start, bad parameters" + (file ? " in " + params_path : std::string()) + ":" +
                     joinLines(errors));
  for (const std::string& mapping : legacy_mappings)
    std::cerr << "prefilter_bag: " << mapping << "\n";
  if (file)
    for (const std::string& warning : ros_io::unusedParameterWarnings(
             file->unusedNames(), *file, "prefilter_bag in input mode " + modeNames(options.input_mode)))
      std::cerr << "prefilter_bag: warning: " << warning << "\n";
  if (given.count("--input-topic") > 0)
    options.input.input_topic = given["--input-topic"];
  if (given.count("--echo1-topic") > 0)
    options.input.echo1_topic = given["--echo1-topic"];
  if (given.count("--echo2-topic") > 0)
    options.input.echo2_topic = given["--echo2-topic"];
  // A topic option the chosen mode does not read is a mistake, not something to ignore.
  std::set<std::string> mode_options;
  const std::unique_ptr<ros_io::InputAdapter> adapter = mode->make(options.input);
  for (const std::unique_ptr<ros_io::InputTopic>& topic : adapter->topics())
    mode_options.insert(topic->option);
  for (const char* option : { "--input-topic", "--echo1-topic", "--echo2-topic" })
    if (given.count(option) > 0 && mode_options.count(option) == 0)
      throw UsageError(std::string(option) + " does not apply to input mode " + modeNames(options.input_mode));
  if (given.count("--prefix") > 0)
  {
    std::string prefix = given["--prefix"];
    if (prefix[0] != '/')
      prefix = "/" + prefix;
    while (prefix.size() > 1 && prefix.back() == '/')
      prefix.pop_back();
    options.prefix = prefix;
  }
  return true;
}
}  // namespace

int main(int argc, char** argv)
{
  ros_io::BagToolOptions options;
  try
  {
    if (!parseCommandLine(argc, argv, options))
    {
      printHelp(std::cout);
      return 0;
    }
  }
  catch (const UsageError& e)
  {
    std::cerr << "prefilter_bag: " << e.what() << "\n(prefilter_bag --help for usage)\n";
    return kExitUsage;
  }

  struct sigaction action;
  std::memset(&action, 0, sizeof(action));
  action.sa_handler = onSignal;
  action.sa_flags = SA_RESETHAND;  // a second Ctrl-C kills at once (leaving only OUT.partial)
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  options.stop = &g_stop;

  ros_io::BagToolSummary summary;
  try
  {
    summary = ros_io::runPrefilterBag(options, std::cerr);
  }
  catch (const std::exception& e)
  {
    std::cerr << "prefilter_bag: " << e.what() << "\n";
    return kExitFailure;
  }
  ros_io::printSummary(summary, std::cerr);
  if (summary.interrupted)
    return kExitInterrupted;
  std::cerr << "prefilter_bag: wrote " << options.output_path << "\n";
  if (summary.sweeps_processed == 0)
    std::cerr << "prefilter_bag: warning: no sweep was processed\n";
  return 0;
}
