#include "ohm_mirror_detector3d/core/output_records.h"

#include <cstring>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
// Through a local record and memcpy: the destination is a byte buffer (a message's data, a
// numpy array), and every byte of the record, padding included, is set.
inline void writeRecord(std::uint8_t* out, const Eigen::Vector3f& position, float intensity, Label label,
                        std::uint8_t echo, std::uint32_t beam)
{
  OutputRecord record;
  record.x = position.x();
  record.y = position.y();
  record.z = position.z();
  record.intensity = intensity;
  record.label = static_cast<std::uint8_t>(label);
  record.echo = echo;
  record.padding[0] = record.padding[1] = 0;
  record.beam = beam;
  std::memcpy(out, &record, sizeof(record));
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
