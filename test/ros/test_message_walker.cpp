// The run-time message reader and writer (definition parser, byte walker, serializer, md5)
// and the hokuyo3d_legacy decoder on hand-made definitions and bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/md5.h"
#include "ohm_mirror_detector3d/ros/message_walker.h"

namespace ohm_mirror_detector3d
{
namespace
{
using ros_io::FieldLocation;

// Little-endian ROS 1 serialization, by hand.
struct Bytes
{
  std::vector<std::uint8_t> data;

  template <typename T>
  Bytes& put(T value)
  {
    const std::size_t at = data.size();
    data.resize(at + sizeof(T));
    std::memcpy(data.data() + at, &value, sizeof(T));
    return *this;
  }
  Bytes& string(const std::string& text)
  {
    put<std::uint32_t>(static_cast<std::uint32_t>(text.size()));
    data.insert(data.end(), text.begin(), text.end());
    return *this;
  }
  template <typename T>
  Bytes& array(const std::vector<T>& values, bool with_length = true)
  {
    if (with_length)
      put<std::uint32_t>(static_cast<std::uint32_t>(values.size()));
    for (const T& value : values)
      put<T>(value);
    return *this;
  }
  Bytes& header(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec, const std::string& frame)
  {
    return put(seq).put(sec).put(nsec).string(frame);
  }
};

const char* const kHeaderSection =
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "# Standard metadata\n"
    "uint32 seq\n"
    "time stamp\n"
    "string frame_id\n";

TEST(MessageWalker, ParsesBuiltinsArraysConstantsCommentsAndNestedTypes)
{
  const std::string text = std::string(
                               "# a test message\n"
                               "uint8 KIND_A=1  # a constant takes no bytes\n"
                               "string GREETING=hello # there\n"
                               "Header header\n"
                               "int16 small   # trailing comment\n"
                               "float64[2] pair\n"
                               "string[] names\n"
                               "Part[] parts\n"
                               "duration wait\n"
                               "bool flag\n"
                               "================================================================================\n"
                               "MSG: test_pkg/Part\n"
                               "int64 id\n"
                               "uint8[] blob\n") +
                           kHeaderSection;
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse("test_pkg/Thing", text), "");
  const ros_io::MessageSpec& root = definition.root();
  ASSERT_EQ(root.fields.size(), 7u);
  EXPECT_EQ(root.fields[0].type, "std_msgs/Header");
  EXPECT_EQ(root.fields[2].typeName(), "float64[2]");
  EXPECT_EQ(root.fields[4].typeName(), "test_pkg/Part[]");
  ASSERT_NE(root.fields[4].nested, nullptr);
  EXPECT_EQ(root.fields[4].nested->fields[1].typeName(), "uint8[]");

  Bytes bytes;
  bytes.header(7, 100, 200, "laser").put<std::int16_t>(-3).array<double>({ 1.5, 2.5 }, false);
  bytes.put<std::uint32_t>(2).string("a").string("bc");
  bytes.put<std::uint32_t>(2).put<std::int64_t>(11).array<std::uint8_t>({ 1, 2, 3 });
  bytes.put<std::int64_t>(12).array<std::uint8_t>({});
  bytes.put<std::int32_t>(5).put<std::int32_t>(6).put<std::uint8_t>(1);

  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data.data(), bytes.data.size(), at), "");
  EXPECT_EQ(at.at("header.seq").offset, 0u);
  EXPECT_EQ(at.at("header.stamp").offset, 4u);
  EXPECT_EQ(at.at("header.frame_id").offset, 16u);
  EXPECT_EQ(at.at("header.frame_id").count, 5u);
  EXPECT_EQ(at.at("small").offset, 21u);
  EXPECT_EQ(at.at("pair").offset, 23u);
  EXPECT_EQ(at.at("pair").count, 2u);
  EXPECT_EQ(at.at("names").count, 2u);
  EXPECT_EQ(at.at("parts").count, 2u);
  const FieldLocation& blob = at.at("parts[0].blob");
  EXPECT_EQ(blob.count, 3u);
  EXPECT_EQ(bytes.data[blob.offset + 2], 3);
  EXPECT_EQ(at.at("parts[1].blob").count, 0u);
  std::int64_t id = 0;
  std::memcpy(&id, bytes.data.data() + at.at("parts[1].id").offset, 8);
  EXPECT_EQ(id, 12);
  EXPECT_EQ(bytes.data[at.at("flag").offset], 1);
  EXPECT_EQ(at.at("flag").offset + 1, bytes.data.size());
}

TEST(MessageWalker, ReportsUnknownTypesMalformedLinesAndShortOrLongBytes)
{
  ros_io::MessageDefinition definition;
  EXPECT_EQ(definition.parse("pkg/A", "Missing thing\n"),
            "message definition of pkg/A uses type 'Missing' (line 1 ('Missing thing') of pkg/A) but has no "
            "'MSG: pkg/Missing' section");
  EXPECT_NE(definition.parse("pkg/A", "float32[x] values\n").find("malformed array size 'x'"), std::string::npos);
  EXPECT_NE(definition.parse("pkg/A", "float32 a b\n").find("expected 'type name'"), std::string::npos);

  ASSERT_EQ(definition.parse("pkg/A", "uint32 n\nfloat32[] values\n"), "");
  std::map<std::string, FieldLocation> at;
  Bytes short_bytes;
  short_bytes.put<std::uint32_t>(1).put<std::uint32_t>(3).put<float>(1.0f);
  EXPECT_NE(ros_io::walkMessage(definition, short_bytes.data.data(), short_bytes.data.size(), at)
                .find("the message ends inside 'values'"),
            std::string::npos);
  Bytes long_bytes;
  long_bytes.put<std::uint32_t>(1).array<float>({ 1.0f }).put<std::uint8_t>(0);
  EXPECT_NE(ros_io::walkMessage(definition, long_bytes.data.data(), long_bytes.data.size(), at)
                .find("1 bytes left over"),
            std::string::npos);
  // A length prefix claiming more elements than there are bytes must not overflow.
  Bytes huge;
  huge.put<std::uint32_t>(1).put<std::uint32_t>(0xFFFFFFFFu);
  EXPECT_NE(ros_io::walkMessage(definition, huge.data.data(), huge.data.size(), at).find("ends inside 'values'"),
            std::string::npos);
}

// The legacy message's definition as the original driver's publisher would send it,
// optionally without one of Coord's fields.
std::string legacyDefinition(const std::string& drop = "")
{
  std::string coord =
      "Header header\nuint32 fragmentid\nuint32 fragmentsize\nfloat32[] coords\nfloat32[] normals\n"
      "bool[] mask\nfloat32[] intensity\nint32[] objectType\n";
  if (!drop.empty())
  {
    const std::size_t at = coord.find(drop + "\n");
    coord.erase(at, drop.size() + 1);
  }
  const std::string line = "================================================================================\n";
  return "CoordDist[] coorddist\n" + line + "MSG: ohm_hokuyo3d/CoordDist\nCoord coord\nDist dist\n" + line +
         "MSG: ohm_hokuyo3d/Coord\n" + coord + kHeaderSection + line +
         "MSG: ohm_hokuyo3d/Dist\nHeader header\nfloat32[] dists\nfloat32[] phi\nbool[] mask\n";
}

struct LegacyEcho
{
  std::vector<float> coords;
  std::vector<std::uint8_t> mask;
  std::vector<float> intensity;
};

Bytes legacyBytes(const std::vector<LegacyEcho>& echoes, const std::string& drop = "")
{
  Bytes bytes;
  bytes.put<std::uint32_t>(static_cast<std::uint32_t>(echoes.size()));
  for (const LegacyEcho& echo : echoes)
  {
    const std::size_t n = echo.mask.size();
    bytes.header(3, 1500, 250, "laser").put<std::uint32_t>(0).put<std::uint32_t>(1);
    if (drop != "float32[] coords")
      bytes.array(echo.coords);
    bytes.array(std::vector<float>(3 * n, 0.5f)).array(echo.mask).array(echo.intensity);
    bytes.array(std::vector<std::int32_t>(n, 0));
    bytes.header(3, 1500, 250, "laser").array(std::vector<float>(n, 1.0f)).array(std::vector<float>(1, 0.0f));
    bytes.array(echo.mask);
  }
  return bytes;
}

const std::vector<LegacyEcho> kTwoEchoes = {
  { { 1, 0, 0, 2, 0, 0, 9, 9, 9 }, { 1, 1, 0 }, { 10, 20, 30 } },
  { { 1, 0, 0, 3, 0, 0, 9, 9, 9 }, { 1, 1, 0 }, { 11, 21, 31 } },
};

TEST(Hokuyo3dLegacy, DecodesBothEchoesHonouringTheMaskAndTakesTheFirstHeader)
{
  ros_io::Hokuyo3dLegacyDecoder decoder;
  const Bytes bytes = legacyBytes(kTwoEchoes);
  core::Sweep sweep;
  std_msgs::Header header;
  ASSERT_EQ(decoder.decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition(), bytes.data.data(), bytes.data.size(),
                           sweep, header),
            "");
  EXPECT_EQ(header.frame_id, "laser");
  EXPECT_EQ(header.stamp.sec, 1500u);
  EXPECT_EQ(header.stamp.nsec, 250u);
  EXPECT_EQ(header.seq, 3u);
  ASSERT_EQ(sweep.rows, 1u);
  ASSERT_EQ(sweep.cols, 3u);
  EXPECT_TRUE(sweep.has_intensity);
  EXPECT_TRUE(sweep.input_cells.empty());
  EXPECT_FLOAT_EQ(sweep.echoes[0].ranges[1], 2.0f);
  EXPECT_FLOAT_EQ(sweep.echoes[1].ranges[1], 3.0f);
  EXPECT_FLOAT_EQ(sweep.echoes[1].intensities[0], 11.0f);
  EXPECT_FALSE(sweep.echoes[0].points[2].allFinite());  // mask false: no return
  EXPECT_FALSE(sweep.echoes[1].points[2].allFinite());
}

TEST(Hokuyo3dLegacy, OneCoordDistIsASingleEchoSweep)
{
  ros_io::Hokuyo3dLegacyDecoder decoder;
  const Bytes bytes = legacyBytes({ kTwoEchoes[0] });
  core::Sweep sweep;
  std_msgs::Header header;
  ASSERT_EQ(decoder.decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition(), bytes.data.data(), bytes.data.size(),
                           sweep, header),
            "");
  EXPECT_TRUE(sweep.echoes[0].points[0].allFinite());
  EXPECT_FALSE(sweep.echoes[1].points[0].allFinite());
}

TEST(Hokuyo3dLegacy, ClearErrorsNameWhatIsMissingOrWrong)
{
  core::Sweep sweep;
  std_msgs::Header header;
  {
    ros_io::Hokuyo3dLegacyDecoder decoder;
    const Bytes bytes = legacyBytes(kTwoEchoes, "float32[] coords");
    const std::string problem = decoder.decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition("float32[] coords"),
                                               bytes.data.data(), bytes.data.size(), sweep, header);
    EXPECT_EQ(problem, "has no field 'coorddist[0].coord.coords'");
  }
  {
    ros_io::Hokuyo3dLegacyDecoder decoder;
    const Bytes bytes = legacyBytes(kTwoEchoes);
    EXPECT_EQ(decoder.decode("other/Type", "float32[] coords\n", bytes.data.data(), bytes.data.size(), sweep, header),
              "message definition of other/Type has no field 'coorddist' (expected CoordDist[] coorddist)");
  }
  {
    std::vector<LegacyEcho> uneven = kTwoEchoes;
    uneven[1].intensity.pop_back();
    ros_io::Hokuyo3dLegacyDecoder decoder;
    const Bytes bytes = legacyBytes(uneven);
    EXPECT_EQ(decoder.decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition(), bytes.data.data(), bytes.data.size(),
                             sweep, header),
              "field 'coorddist[1].coord.intensity' holds 2 values for 3 points");
  }
  {
    ros_io::Hokuyo3dLegacyDecoder decoder;
    Bytes bytes = legacyBytes(kTwoEchoes);
    bytes.data.resize(bytes.data.size() - 2);
    EXPECT_NE(decoder
                  .decode("ohm_hokuyo3d/CoordDistMulti", legacyDefinition(), bytes.data.data(), bytes.data.size(),
                          sweep, header)
                  .find("ends inside 'coorddist[1].dist.mask'"),
              std::string::npos);
  }
}

TEST(MessageWalker, KeepsConstantsAsGenmsgReadsThem)
{
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse("test_pkg/Consts", "int8 LOW = -1   # spaced\n"
                                                "string WORDS= a # not a comment \n"
                                                "uint8 x\n"),
            "");
  const std::vector<ros_io::ConstantSpec>& constants = definition.root().constants;
  ASSERT_EQ(constants.size(), 2u);
  EXPECT_EQ(constants[0].type, "int8");
  EXPECT_EQ(constants[0].name, "LOW");
  EXPECT_EQ(constants[0].value, "-1");
  EXPECT_EQ(constants[1].name, "WORDS");
  EXPECT_EQ(constants[1].value, "a # not a comment");
  // genmsg's md5 text: constants first, then the fields.
  EXPECT_EQ(ros_io::md5sum(definition.root()), ros_io::md5Hex("int8 LOW=-1\nstring WORDS=a # not a comment\nuint8 x"));
}

TEST(MessageWalker, Md5IsRfc1321s)
{
  EXPECT_EQ(ros_io::md5Hex(""), "d41d8cd98f00b204e9800998ecf8427e");
  EXPECT_EQ(ros_io::md5Hex("abc"), "900150983cd24fb0d6963f7d28e17f72");
  EXPECT_EQ(ros_io::md5Hex("message digest"), "f96b697d7cb7938d525a2f31aaf161d0");
  // Lengths around the padding limits (55, 56, 64 bytes) and over several blocks.
  EXPECT_EQ(ros_io::md5Hex(std::string(55, 'z')), "b687791f373f9a09b6f18a1d845aecbf");
  EXPECT_EQ(ros_io::md5Hex(std::string(56, 'x')), "668a72d5ba17f08e62dabcafad6db14b");
  EXPECT_EQ(ros_io::md5Hex(std::string(64, 'y')), "b0c4864f4e28d2d76929c38d87db7ed5");
  EXPECT_EQ(ros_io::md5Hex("12345678901234567890123456789012345678901234567890123456789012345678901234567890"),
            "57edf4a22be3c955ac49da2e2107b67a");
}

TEST(MessageWalker, SerializesValuesByPathAndEmptyFieldsOtherwise)
{
  const std::string text = std::string(
                               "Header header\n"
                               "uint8 KIND=3\n"
                               "float32[] values\n"
                               "int16[2] pair\n"
                               "string[] names\n"
                               "Part[] parts\n"
                               "Part[2] fixed_parts\n"
                               "bool flag\n"
                               "================================================================================\n"
                               "MSG: test_pkg/Part\n"
                               "int64 id\n"
                               "string label\n") +
                           kHeaderSection;
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse("test_pkg/Thing", text), "");

  const std::uint32_t seq = 4;
  const std::uint32_t stamp[2] = { 100, 200 };
  const std::string frame = "laser";
  const std::vector<float> values = { 1.5f, -2.0f };
  const std::string names[2] = { "a", "bc" };
  const std::int64_t id = 77;
  const std::string label = "second";
  const std::uint8_t flag = 1;
  ros_io::FieldValues fields;
  fields.set("header.seq", "uint32", &seq, 1);
  fields.set("header.stamp", "time", stamp, 1);
  fields.setString("header.frame_id", frame);
  fields.set("values", "float32", values.data(), values.size());
  fields.set("names", "string", names, 2);
  fields.setCount("parts", 2);
  fields.set("parts[1].id", "int64", &id, 1);
  fields.setString("parts[1].label", label);
  fields.set("flag", "bool", &flag, 1);
  fields.set("not_a_field", "float32", values.data(), values.size());
  std::vector<std::uint8_t> bytes;
  ASSERT_EQ(ros_io::serializeMessage(definition.root(), fields, bytes), "");

  // Byte for byte what a hand serialization of the same values gives.
  Bytes expected;
  expected.header(4, 100, 200, "laser").array<float>(values).put<std::int16_t>(0).put<std::int16_t>(0);
  expected.put<std::uint32_t>(2).string("a").string("bc");
  expected.put<std::uint32_t>(2).put<std::int64_t>(0).string("").put<std::int64_t>(77).string("second");
  expected.put<std::int64_t>(0).string("").put<std::int64_t>(0).string("");
  expected.put<std::uint8_t>(1);
  EXPECT_EQ(bytes, expected.data);

  std::map<std::string, FieldLocation> at;
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  EXPECT_EQ(at.at("fixed_parts[1].label").count, 0u);

  // Nothing given: every field empty.
  ASSERT_EQ(ros_io::serializeMessage(definition.root(), ros_io::FieldValues(), bytes), "");
  ASSERT_EQ(ros_io::walkMessage(definition, bytes.data(), bytes.size(), at), "");
  EXPECT_EQ(at.at("values").count, 0u);
  EXPECT_EQ(at.at("parts").count, 0u);
  EXPECT_EQ(at.at("fixed_parts").count, 2u);
}

TEST(MessageWalker, SerializerNamesValuesThatDoNotFitTheirField)
{
  ros_io::MessageDefinition definition;
  ASSERT_EQ(definition.parse("test_pkg/Small", "float32[] values\nint16[2] pair\nPart part\n"
                                               "================================================================================\n"
                                               "MSG: test_pkg/Part\nint64 id\n"),
            "");
  const double wide[2] = { 1.0, 2.0 };
  const std::int16_t three[3] = { 1, 2, 3 };
  std::vector<std::uint8_t> bytes;
  ros_io::FieldValues fields;
  fields.set("values", "float64", wide, 2);
  EXPECT_EQ(ros_io::serializeMessage(definition.root(), fields, bytes),
            "'values' is float32[] but was given float64 values");
  fields.clear();
  fields.set("pair", "int16", three, 3);
  EXPECT_EQ(ros_io::serializeMessage(definition.root(), fields, bytes), "'pair' is int16[2] but was given 3 elements");
  fields.clear();
  fields.set("part", "int64", wide, 1);
  EXPECT_EQ(ros_io::serializeMessage(definition.root(), fields, bytes),
            "'part' is test_pkg/Part but was given int64 values");
  fields.clear();
  fields.setCount("part.id", 1);
  EXPECT_EQ(ros_io::serializeMessage(definition.root(), fields, bytes), "'part.id' is int64 but was given an element count");
}

}  // namespace
}  // namespace ohm_mirror_detector3d
