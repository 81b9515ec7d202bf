#include "common/zlib_codec.hpp"

#include <zlib.h>

#include <stdexcept>

namespace pslam::server {

std::vector<std::uint8_t> ZlibCompress(std::span<const std::uint8_t> data, int level) {
  uLongf size = compressBound(static_cast<uLong>(data.size()));
  std::vector<std::uint8_t> out(size);
  if (compress2(out.data(), &size, data.data(), static_cast<uLong>(data.size()), level) != Z_OK) {
    throw std::runtime_error("zlib compression failed");
  }
  out.resize(size);
  return out;
}

std::optional<std::vector<std::uint8_t>> ZlibDecompress(std::span<const std::uint8_t> data, std::size_t max_size) {
  std::vector<std::uint8_t> out(max_size);
  z_stream stream{};
  if (inflateInit(&stream) != Z_OK) return std::nullopt;
  stream.next_in = const_cast<Bytef*>(data.data());
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = out.data();
  stream.avail_out = static_cast<uInt>(out.size());
  const int rc = inflate(&stream, Z_FINISH);
  const std::size_t produced = stream.total_out;
  inflateEnd(&stream);
  if (rc != Z_STREAM_END) return std::nullopt;  // corrupt, truncated, or larger than max_size
  out.resize(produced);
  return out;
}

std::uint32_t Crc32(std::span<const std::uint8_t> data, std::uint32_t crc) {
  return static_cast<std::uint32_t>(crc32(crc, data.data(), static_cast<uInt>(data.size())));
}

}  // namespace pslam::server
