#include "common/png_writer.hpp"

#include <stdexcept>
#include <string_view>

#include "common/zlib_codec.hpp"

namespace pslam::server {
namespace {

void PutU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void PutChunk(std::vector<std::uint8_t>& out, std::string_view type, std::span<const std::uint8_t> data) {
  PutU32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type.begin(), type.end());
  out.insert(out.end(), data.begin(), data.end());
  // The CRC covers the chunk type and data, not the length.
  PutU32(out, Crc32(std::span<const std::uint8_t>(out.data() + type_at, out.size() - type_at)));
}

}  // namespace

std::vector<std::uint8_t> EncodePng(int width, int height, int channels, std::span<const std::uint8_t> pixels) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 4) ||
      pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels)) {
    throw std::invalid_argument("EncodePng: image size does not match its pixels");
  }
  const std::size_t stride = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  std::vector<std::uint8_t> raw;
  raw.reserve((stride + 1) * static_cast<std::size_t>(height));
  for (int row = 0; row < height; ++row) {
    raw.push_back(0);  // filter type None: maps are mostly flat runs, which deflate handles well
    const auto begin = pixels.begin() + static_cast<std::ptrdiff_t>(stride * static_cast<std::size_t>(row));
    raw.insert(raw.end(), begin, begin + static_cast<std::ptrdiff_t>(stride));
  }
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  PutU32(header, static_cast<std::uint32_t>(width));
  PutU32(header, static_cast<std::uint32_t>(height));
  header.push_back(8);                               // bit depth
  header.push_back(channels == 1 ? 0 : 6);           // colour type: grey or RGBA
  header.insert(header.end(), {0, 0, 0});            // deflate, adaptive filtering, no interlace
  PutChunk(out, "IHDR", header);
  PutChunk(out, "IDAT", ZlibCompress(raw));
  PutChunk(out, "IEND", {});
  return out;
}

}  // namespace pslam::server
