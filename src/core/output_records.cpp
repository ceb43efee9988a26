#include "ohm_mirror_detector3d/core/output_records.h"

#include <cstring>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Field by field into the byte buffer (a message's data, a numpy array), padding included. (A
// record built on the stack and copied whole is twice as slow: its 16-byte load waits for the
// narrower stores before it.)
inline void writeRecord(std::uint8_t* out, const Eigen::Vector3f& position, float intensity, Label label,
                        std::uint8_t echo, std::uint32_t beam)
{
  std::memcpy(out + offsetof(OutputRecord, x), position.data(), 3 * sizeof(float));
  std::memcpy(out + offsetof(OutputRecord, intensity), &intensity, sizeof(float));
  out[offsetof(OutputRecord, label)] = static_cast<std::uint8_t>(label);
  out[offsetof(OutputRecord, echo)] = echo;
  out[offsetof(OutputRecord, padding)] = 0;
  out[offsetof(OutputRecord, padding) + 1] = 0;
  std::memcpy(out + offsetof(OutputRecord, beam), &beam, sizeof(beam));
}
}  // namespace

const std::array<OutputField, 7>& outputFields()
{
  static const std::array<OutputField, 7> fields = { {
      { "x", offsetof(OutputRecord, x), OutputFieldType::float32 },
      { "y", offsetof(OutputRecord, y), OutputFieldType::float32 },
      { "z", offsetof(OutputRecord, z), OutputFieldType::float32 },
      { "intensity", offsetof(OutputRecord, intensity), OutputFieldType::float32 },
      { "label", offsetof(OutputRecord, label), OutputFieldType::uint8 },
      { "echo", offsetof(OutputRecord, echo), OutputFieldType::uint8 },
      { "beam", offsetof(OutputRecord, beam), OutputFieldType::uint32 },
  } };
  return fields;
}

std::size_t labelledRecordCount(const Sweep& sweep)
{
  return sweep.input_cells.empty() ? 2 * sweep.beamCount() : sweep.input_cells.size();
}

void writeLabelledRecords(const Sweep& sweep, const SweepLabels& labels, std::uint8_t* out)
{
  if (!sweep.input_cells.empty())
  {
    // The input's own order and count (a dual-return cloud), so labels join back onto it.
    for (const PointRef& cell : sweep.input_cells)
    {
      if (cell.echo == PointRef::kNoCell)
        writeRecord(out, sweep.unbinned.points[cell.beam], sweep.unbinned.intensities[cell.beam], Label::nanPoint, 0,
                    kNoBeam);
      else
        writeRecord(out, sweep.echoes[cell.echo].points[cell.beam], sweep.echoes[cell.echo].intensities[cell.beam],
                    labels.echoes[cell.echo][cell.beam], static_cast<std::uint8_t>(cell.echo + 1), cell.beam);
      out += sizeof(OutputRecord);
    }
    return;
  }
  const std::size_t beams = sweep.beamCount();
  for (std::size_t k = 0; k < 2; ++k)
  {
    const EchoCloud& echo = sweep.echoes[k];
    for (std::size_t i = 0; i < beams; ++i, out += sizeof(OutputRecord))
      writeRecord(out, echo.points[i], echo.intensities[i], labels.echoes[k][i], static_cast<std::uint8_t>(k + 1),
                  static_cast<std::uint32_t>(i));
  }
}

void writeCleanedRecords(const std::vector<OutputPoint>& points, std::uint8_t* out)
{
  for (const OutputPoint& point : points)
  {
    writeRecord(out, point.position, point.intensity, point.label, point.echo, point.beam);
    out += sizeof(OutputRecord);
  }
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
