#pragma once
// CRC-32 (IEEE 802.3, zlib's polynomial 0xEDB88320) for spool records. Table-driven; the table is
// built once at compile time.
#include <array>
#include <cstdint>
#include <span>

namespace pslam::agent {

namespace detail {
constexpr std::array<std::uint32_t, 256> MakeCrc32Table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}
inline constexpr std::array<std::uint32_t, 256> kCrc32Table = MakeCrc32Table();
}  // namespace detail

// Continues 'crc' (0 to start) over 'bytes'; Crc32(b) == Crc32(b2, Crc32(b1)) for b = b1 + b2.
inline std::uint32_t Crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0) {
  crc = ~crc;
  for (std::uint8_t b : bytes) crc = detail::kCrc32Table[(crc ^ b) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

}  // namespace pslam::agent
