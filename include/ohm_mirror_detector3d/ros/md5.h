// MD5 (RFC 1321) of a byte string, as lowercase hex: what ROS 1 uses to fingerprint a message
// type (see MessageDefinition::md5sum). No ROS includes.
#pragma once

#include <string>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
std::string md5Hex(const std::string& bytes);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
