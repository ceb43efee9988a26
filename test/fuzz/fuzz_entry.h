// One fuzz input through an input adapter and the whole pipeline. Shared by the libFuzzer
// target (test/fuzz/fuzz_prefilter.cpp, `make fuzz`) and the corpus replay test
// (test/fuzz/test_fuzz_corpus.cpp, part of `make test`), so a reproducer found by the fuzzer
// runs through exactly the same code under the normal compiler.
//
// Input layout: byte 0 picks the input mode, byte 1 the parameter set, the rest is the
// serialized message(s) of that mode as a ROS publisher sends them:
//   0 pair            ohm_mirror_detector3d/EchoPair
//   1 two_topics      an EchoPair whose echo1 and echo2 go through the two_topics converter
//   2 dual_return     sensor_msgs/PointCloud2
//   3 hokuyo3d_legacy ohm_hokuyo3d/CoordDistMulti (decoded from its definition)
//   4 multi_echo_scan sensor_msgs/MultiEchoLaserScan messages, each preceded by its uint32
//                     length (little endian); frame "laser" is static in sweep frame "map"
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace ohm_mirror_detector3d
{
namespace fuzz
{
enum class FuzzMode : std::uint8_t
{
  pair = 0,
  two_topics = 1,
  dual_return = 2,
  hokuyo3d_legacy = 3,
  multi_echo_scan = 4
};
constexpr std::uint8_t kFuzzModes = 5;

// What happened to one input, for the replay test's summary.
struct FuzzOutcome
{
  bool deserialized = false;   // the bytes held a well-formed message
  bool converted = false;      // the adapter accepted it (otherwise `problem` says why)
  std::size_t sweeps = 0;      // sweeps that went through the pipeline
  std::string problem;
};

// Runs one input. Aborts (so libFuzzer and the replay test report it) when an invariant of
// the outputs breaks: the labelled cloud must hold one point per input point of both
// echoes, every label must be a known one, and the cleaned cloud no more points than that.
FuzzOutcome runFuzzInput(const std::uint8_t* data, std::size_t size);

// The definition of ohm_hokuyo3d/CoordDistMulti the fuzzer decodes with.
const std::string& legacyDefinition();

}  // namespace fuzz
}  // namespace ohm_mirror_detector3d
