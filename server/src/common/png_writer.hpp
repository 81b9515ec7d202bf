#pragma once
// A minimal PNG encoder (8-bit grey or RGBA, no interlace) on zlib. The core's PNG export goes
// through OpenCV; the server needs PNGs of its own (hypothesis overlays) and should not pull
// OpenCV into the network process for that.
#include <cstdint>
#include <span>
#include <vector>

namespace pslam::server {

// 'pixels' is row-major, row 0 at the top, 'channels' bytes per pixel (1: grey, 4: RGBA).
std::vector<std::uint8_t> EncodePng(int width, int height, int channels, std::span<const std::uint8_t> pixels);

}  // namespace pslam::server
