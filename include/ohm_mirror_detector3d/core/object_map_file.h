// The object map as a file, so that a robot keeps what it learned across restarts: YAML, one
// entry per map object (plane, the cells of its extent as rows of 0/1, log-odds, sweeps seen).
// yaml-cpp reads and writes it: the package already depends on it (prefilter_bag's --params),
// every ROS robot has it, and a real parser turns any malformed or truncated file into an error
// message instead of a hand-written reader's guesswork.
#pragma once

#include <string>

#include "ohm_mirror_detector3d/core/object_map.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// The file format's name and version: a file with others is refused.
constexpr const char* kObjectMapFormat = "ohm_mirror_detector3d/object_map";
constexpr int kObjectMapVersion = 1;

// Writes `map` (in `fixed_frame`) to `path`; "" or what went wrong.
std::string saveObjectMap(const std::string& path, const std::string& fixed_frame, const ObjectMap& map);

// Replaces the objects of `map` by those in `path`. A file that cannot be read, is no map file,
// has another version, another fixed frame than `fixed_frame`, another cell size than the
// map's config or any bad entry is refused as a whole: the map is left empty and the message
// says what is wrong (never an exception).
std::string loadObjectMap(const std::string& path, const std::string& fixed_frame, ObjectMap& map);

}  // namespace core
}  // namespace ohm_mirror_detector3d
