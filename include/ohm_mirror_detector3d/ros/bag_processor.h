// prefilter_bag's processing loop: the nodelet's input path (SweepInput: the input mode's
// adapter, the wait for sensor_frame's transform) and pipeline (MessagePipeline) over every
// message of a bag, in bag order, without a master; tf comes from the bag's /tf and /tf_static.
// src/ros/prefilter_bag.cpp is its command line.
#pragma once

#include <csignal>
#include <cstddef>
#include <map>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/ros/input_mode.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
struct BagToolOptions
{
  std::string input_path;
  std::string output_path;
  // A name of inputModes(); "": the type on the input topic in the bag chooses (modeFromBag).
  std::string input_mode;
  InputOptions input;
  core::Params params;
  std::string prefix = "/prefilter";  // outputs: prefix + /labelled, /cleaned, /objects, /markers
  bool only_outputs = false;          // else every other message of the input is copied too
  bool verbose = false;               // a line per sweep
  // Set (by a signal handler) to stop after the current sweep; the output is then removed.
  const volatile std::sig_atomic_t* stop = nullptr;
};

struct BagToolSummary
{
  std::size_t input_messages = 0;   // messages read on the mode's topics (and /tf, /tf_static when used)
  std::size_t copied_messages = 0;  // messages copied through unchanged
  std::size_t sweeps_processed = 0;
  std::size_t sweeps_dropped = 0;
  std::map<std::string, std::size_t> drop_reasons;     // reason -> count
  std::map<std::string, std::size_t> objects_by_type;  // "mirror", "glass", "unknown" -> count
  std::vector<double> sweep_seconds;  // per sweep: conversion + pipeline + output messages
  double wall_seconds = 0.0;
  bool interrupted = false;  // stopped by `stop`; no output was left
};

// A problem that stops the tool (unreadable input, missing topic, bad parameters, ...);
// what() is the message for the user.
class BagToolError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

// The partial output's name: OUT is written under it and renamed when complete.
std::string partialOutputPath(const std::string& output_path);

// Runs the pre-filter over options.input_path and writes options.output_path. Progress,
// dropped sweeps and (verbose) per-sweep lines go to `log`. The output only appears when
// complete: on a BagToolError or an interruption the partial file is removed and no
// output_path is created.
BagToolSummary runPrefilterBag(const BagToolOptions& options, std::ostream& log);

// The final summary: sweeps processed and dropped (by reason), objects by type, per-sweep
// time median and p95, throughput, wall time.
void printSummary(const BagToolSummary& summary, std::ostream& out);

// q-quantile (0..1, nearest rank) of `values`; NaN when empty.
double quantile(std::vector<double> values, double q);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
