// Binary PSC1 scan frames, decoded against a laser whose beam count matches the frame's length (so
// the range checks are reached; a laser has at least one beam, as ParseLaserGeometry ensures) and
// against none. Bad frames must be an IngestError, never a crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <variant>

#include "service/ingest_codec.hpp"

using namespace pslam::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  LaserGeometry laser;
  laser.angle_min = -1.5707963;
  laser.angle_increment = 0.0174533;
  laser.max_range = 8.0;
  laser.beams = size >= 52 ? static_cast<int>((size - 48) / 4) : 181;
  (void)DecodeBinaryScan(bytes, nullptr);
  const IngestMessage message = DecodeBinaryScan(bytes, &laser);
  if (const auto* input = std::get_if<InputRecord>(&message)) {
    if (input->ranges.size() != static_cast<std::size_t>(laser.beams)) std::abort();
    if (!std::isfinite(input->t) || !std::isfinite(input->x) || !std::isfinite(input->y) || !std::isfinite(input->theta)) {
      std::abort();
    }
    for (float r : input->ranges) {
      if (r < 0.0f || std::isinf(r)) std::abort();
    }
  }
  return 0;
}
