// A small reader of ROS 1 messages whose type is known only at run time: parses the full
// message definition a publisher sends in its connection header (the main message, then
// one `MSG: pkg/Type` section per nested type) and walks the serialized bytes to find the
// fields by name. No ROS includes: testable with hand-made definitions and bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
struct MessageSpec;

// One field of a message definition.
struct FieldSpec
{
  std::string type;        // element type as written after resolution: "float32", "std_msgs/Header", ...
  std::string name;
  bool is_array = false;
  std::int64_t array_size = -1;  // fixed-size array length; -1 for a variable-length array
  const MessageSpec* nested = nullptr;  // the element's definition when it is a message type

  // "float32[]", "ohm_hokuyo3d/Coord", "uint8[16]", ... for messages.
  std::string typeName() const;
};

struct MessageSpec
{
  std::string name;  // full name "pkg/Type"
  std::vector<FieldSpec> fields;
};

// A parsed definition: the main message and every nested type it uses.
class MessageDefinition
{
public:
  // Parses the full text of `datatype` ("pkg/Type"). Returns an empty string on success,
  // otherwise what is wrong (unknown type, malformed line, ...), naming it.
  std::string parse(const std::string& datatype, const std::string& text);

  const MessageSpec& root() const { return *root_; }
  const std::string& datatype() const { return datatype_; }

private:
  std::string datatype_;
  std::map<std::string, std::unique_ptr<MessageSpec>> specs_;  // by full name
  const MessageSpec* root_ = nullptr;
};

// Where a field is in the serialized bytes. For an array of builtins, `offset` is the start
// of its elements (after the length prefix of a variable-length array) and `count` their
// number; for a scalar builtin count is 1; for a string `offset` is the start of its
// characters and `count` their number; for a message (or an array of messages) `offset`
// is its start and `count` the element count.
struct FieldLocation
{
  const FieldSpec* field = nullptr;
  std::size_t offset = 0;
  std::size_t count = 0;
};

// Walks `size` bytes of a message of `definition` and stores the location of every field
// under its path: "header.stamp", "coorddist[1].coord.coords", ... (array elements of
// message type get an index; arrays of builtins are one entry). Returns an empty string on
// success, otherwise where the bytes end early or are left over.
std::string walkMessage(const MessageDefinition& definition, const std::uint8_t* data, std::size_t size,
                        std::map<std::string, FieldLocation>& locations);

// Bytes of one element of a fixed-size builtin type ("float32" 4, "time" 8, ...); 0 for
// string and message types.
std::size_t builtinSize(const std::string& type);
bool isBuiltin(const std::string& type);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
