// A small reader and writer of ROS 1 messages whose type is known only at run time: parses
// the full message definition a publisher sends in its connection header (the main message,
// then one `MSG: pkg/Type` section per nested type), walks serialized bytes to find the
// fields by name, serializes a message from values given by field name, and computes a
// type's md5sum as ROS does. No ROS includes: testable with hand-made definitions and bytes.
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

// A constant ("uint8 TYPE_MIRROR=1"): no bytes in the message, but part of its md5sum.
struct ConstantSpec
{
  std::string type;
  std::string name;
  std::string value;  // as written: to the end of the line for a string, else up to a comment
};

struct MessageSpec
{
  std::string name;  // full name "pkg/Type"
  std::vector<ConstantSpec> constants;
  std::vector<FieldSpec> fields;
  std::string text;  // the section's own lines as given (comments too), for re-announcing it
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

  // The spec of the main message or of one of its nested types by full name; null if absent.
  const MessageSpec* find(const std::string& full_name) const;

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

// The md5sum ROS gives the type of `spec` (genmsg's compute_md5): the md5 of its constants
// ("type name=value") and fields ("type name" for builtins, "<md5 of the type> name" for
// message types, array brackets dropped for those), one per line, comments and blank lines
// left out.
std::string md5sum(const MessageSpec& spec);

// The full definition of `spec` as a publisher of that type announces it (genmsg's
// compute_full_text): its own text, then per nested type, depth first in order of first use,
// a line of 80 '=', "MSG: pkg/Type" and that type's text.
std::string fullDefinition(const MessageSpec& spec);

// Values of the fields of a message to serialize, by the paths walkMessage gives them
// ("header.stamp", "coorddist[1].coord.coords"). The values are not copied: they must
// outlive serializeMessage.
class FieldValues
{
public:
  void clear() { values_.clear(); }

  // `count` elements of builtin type `type` ("float32", "bool", "time", ...) at `data`, as
  // ROS serializes them (little endian; std::string objects for "string"): one for a scalar,
  // the array size for a fixed-size array, any number for a variable-length one.
  void set(const std::string& path, const std::string& type, const void* data, std::size_t count);
  void setString(const std::string& path, const std::string& text);
  // The number of elements of a variable-length array of messages, whose fields are set
  // under "path[k].".
  void setCount(const std::string& path, std::size_t count);

private:
  friend class MessageSerializer;
  struct Value
  {
    std::string type;  // "string" for setString, "" for setCount
    const void* data = nullptr;
    std::size_t count = 0;
  };
  std::map<std::string, Value> values_;
};

// Serializes a message of `spec` into `bytes` (replaced): every field from `values` by its
// path, every field without a value empty (0, false, "", a variable-length array of no
// elements, a fixed-size array of empty elements, a message of empty fields). Returns an
// empty string on success, otherwise which value does not fit its field (type, count).
// Values whose path is no field of `spec` are not written.
std::string serializeMessage(const MessageSpec& spec, const FieldValues& values, std::vector<std::uint8_t>& bytes);

// Bytes of one element of a fixed-size builtin type ("float32" 4, "time" 8, ...); 0 for
// string and message types.
std::size_t builtinSize(const std::string& type);
bool isBuiltin(const std::string& type);

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
