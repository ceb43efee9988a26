// Input mode hokuyo3d_legacy: the tuple message ohm_hokuyo3d/CoordDistMulti of the original
// driver, decoded at run time from the definition its publisher sends (no package needed).
//
// Layout as far as known (fields are found by name; others are skipped):
//   CoordDist[] coorddist                 index 0: echo 1, index 1: echo 2 (further ones ignored)
//   CoordDist { Coord coord; Dist dist }
//   Coord { Header header; uint32 fragmentid; uint32 fragmentsize; float32[] coords (3N);
//           float32[] normals (3N); bool[] mask (N); float32[] intensity (N); int32[] objectType (N) }
//   Dist  { Header header; float32[] dists (N); float32[] phi; bool[] mask (N) }
// Point i of both echoes is the same beam; a beam whose mask is false has no return.
#pragma once

#include <std_msgs/Header.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/ros/message_walker.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
// The original driver's name of the type: "ohm_hokuyo3d/CoordDistMulti".
extern const char* const kLegacyScanDatatype;

// "" when the message definition `definition` of `datatype` has the layout above (a field
// `coorddist`, an array of messages with `coord.coords` of type float32[]), whatever the type's
// name; otherwise what it lacks, naming the field. The default input mode reads such a type
// as hokuyo3d_legacy.
std::string legacyLayoutProblem(const std::string& datatype, const std::string& definition);

class Hokuyo3dLegacyDecoder
{
public:
  // Fills `sweep` (1 x N beams: coords of coorddist[0] as echo 1, of coorddist[1] as echo 2,
  // masked-out beams NaN; a single CoordDist gives a single-echo sweep) and `header` (that
  // of coorddist[0].coord) from one serialized message of `datatype` with the full message
  // definition `definition`. The definition is parsed again only when it changes. Returns
  // an empty string on success, otherwise what is wrong, naming the field.
  std::string decode(const std::string& datatype, const std::string& definition, const std::uint8_t* data,
                     std::size_t size, core::Sweep& sweep, std_msgs::Header& header);

private:
  std::string parseDefinition(const std::string& datatype, const std::string& definition);

  std::string datatype_;
  std::string definition_text_;
  std::string definition_problem_;
  MessageDefinition definition_;
  std::map<std::string, FieldLocation> locations_;
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
