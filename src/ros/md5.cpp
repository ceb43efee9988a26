#include "ohm_mirror_detector3d/ros/md5.h"

#include <array>
#include <cmath>
#include <cstdint>

namespace ohm_mirror_detector3d
{
namespace ros_io
{
namespace
{
std::uint32_t rotateLeft(std::uint32_t value, int bits)
{
  return (value << bits) | (value >> (32 - bits));
}

// RFC 1321, 3.4: K[i] = floor(2^32 |sin(i + 1)|).
std::array<std::uint32_t, 64> sineTable()
{
  std::array<std::uint32_t, 64> table{};
  for (int i = 0; i < 64; ++i)
    table[i] = static_cast<std::uint32_t>(std::floor(std::fabs(std::sin(i + 1.0)) * 4294967296.0));
  return table;
}

void processBlock(const unsigned char* block, std::array<std::uint32_t, 4>& state)
{
  static const std::array<std::uint32_t, 64> kSine = sineTable();
  static const int kShift[4][4] = { { 7, 12, 17, 22 }, { 5, 9, 14, 20 }, { 4, 11, 16, 23 }, { 6, 10, 15, 21 } };
  std::uint32_t words[16];
  for (int i = 0; i < 16; ++i)
    words[i] = static_cast<std::uint32_t>(block[4 * i]) | static_cast<std::uint32_t>(block[4 * i + 1]) << 8 |
               static_cast<std::uint32_t>(block[4 * i + 2]) << 16 | static_cast<std::uint32_t>(block[4 * i + 3]) << 24;
  std::uint32_t a = state[0], b = state[1], c = state[2], d = state[3];
  for (int i = 0; i < 64; ++i)
  {
    const int round = i / 16;
    std::uint32_t mixed;
    int word;
    switch (round)
    {
      case 0:
        mixed = (b & c) | (~b & d);
        word = i;
        break;
      case 1:
        mixed = (d & b) | (~d & c);
        word = (5 * i + 1) % 16;
        break;
      case 2:
        mixed = b ^ c ^ d;
        word = (3 * i + 5) % 16;
        break;
      default:
        mixed = c ^ (b | ~d);
        word = (7 * i) % 16;
        break;
    }
    const std::uint32_t next = b + rotateLeft(a + mixed + kSine[i] + words[word], kShift[round][i % 4]);
    a = d;
    d = c;
    c = b;
    b = next;
  }
  state[0] += a;
  state[1] += b;
  state[2] += c;
  state[3] += d;
}
}  // namespace

std::string md5Hex(const std::string& bytes)
{
  std::array<std::uint32_t, 4> state = { 0x67452301u, 0xefcdab89u, 0x98badcfeu, 0x10325476u };
  const std::size_t full_blocks = bytes.size() / 64;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  for (std::size_t k = 0; k < full_blocks; ++k)
    processBlock(data + 64 * k, state);

  // Padding: a 1 bit, zeros up to 56 bytes modulo 64, the bit length (64 bits, little endian).
  unsigned char tail[128] = {};
  const std::size_t rest = bytes.size() - 64 * full_blocks;
  for (std::size_t i = 0; i < rest; ++i)
    tail[i] = data[64 * full_blocks + i];
  tail[rest] = 0x80;
  const std::size_t tail_size = rest < 56 ? 64 : 128;
  const std::uint64_t bits = static_cast<std::uint64_t>(bytes.size()) * 8;
  for (int i = 0; i < 8; ++i)
    tail[tail_size - 8 + i] = static_cast<unsigned char>(bits >> (8 * i));
  for (std::size_t offset = 0; offset < tail_size; offset += 64)
    processBlock(tail + offset, state);

  static const char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(32);
  for (std::uint32_t word : state)
    for (int i = 0; i < 4; ++i)
    {
      const unsigned byte = (word >> (8 * i)) & 0xffu;
      hex += kHex[byte >> 4];
      hex += kHex[byte & 0xfu];
    }
  return hex;
}

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
