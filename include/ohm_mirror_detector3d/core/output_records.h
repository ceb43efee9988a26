// The point records of the `labelled` and `cleaned` outputs, x y z intensity label echo beam in
// 24 bytes: the byte layout of the nodelet's PointCloud2s and of the Python bindings' structured
// arrays, written by the same code for both (so that their bytes agree).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct OutputRecord
{
  float x;
  float y;
  float z;
  float intensity;
  std::uint8_t label;
  std::uint8_t echo;     // 1 or 2; 0 for an input point in no grid cell
  std::uint8_t padding[2];  // always zero, so that the bytes are reproducible
  std::uint32_t beam;    // the beam's index in the sweep; kNoBeam for an input point in no grid cell
};
static_assert(sizeof(OutputRecord) == 24, "24-byte records");

constexpr std::uint32_t kNoBeam = 0xFFFFFFFFu;

enum class OutputFieldType
{
  float32,
  uint8,
  uint32,
};

struct OutputField
{
  const char* name;
  std::uint32_t offset;
  OutputFieldType type;
};

// The fields of OutputRecord in order, as a PointCloud2 names them.
const std::array<OutputField, 7>& outputFields();

// How many records `labelled` has: one per input point (a sweep with input_cells), or every
// point of both echoes.
std::size_t labelledRecordCount(const Sweep& sweep);

// The labelled records of a processed sweep, every byte of them, into `out`
// (labelledRecordCount(sweep) records): echo 1 first, then echo 2, each in beam order,
// positions as measured; or, when the sweep has input_cells, the input's points in the input's
// order, those in no grid cell as nanPoint with echo 0 and beam kNoBeam.
void writeLabelledRecords(const Sweep& sweep, const SweepLabels& labels, std::uint8_t* out);

// The cleaned points as records, every byte of them, into `out` (points.size() records).
void writeCleanedRecords(const std::vector<OutputPoint>& points, std::uint8_t* out);

}  // namespace core
}  // namespace ohm_mirror_detector3d
