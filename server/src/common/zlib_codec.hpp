#pragma once
// zlib (RFC 1950) compression of byte buffers: map tiles and hypothesis cells are stored and sent
// compressed. Decompression takes the expected size, so a corrupt or hostile blob cannot make us
// allocate more than the caller planned for.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pslam::server {

std::vector<std::uint8_t> ZlibCompress(std::span<const std::uint8_t> data, int level = 6);

// Returns the inflated bytes, or nullopt if 'data' is not a zlib stream that inflates to at most
// 'max_size' bytes.
std::optional<std::vector<std::uint8_t>> ZlibDecompress(std::span<const std::uint8_t> data, std::size_t max_size);

// CRC-32 as PNG chunks use it.
std::uint32_t Crc32(std::span<const std::uint8_t> data, std::uint32_t crc = 0);

}  // namespace pslam::server
