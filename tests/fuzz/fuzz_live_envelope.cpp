// The live fan-out's Redis payloads (service/live_envelope.hpp), as another node might send them,
// fed to a mirror as the subscribing node does: a bad payload must be an error or an exception
// that leaves the mirror as it was, never a crash; a decoded delta must encode and decode again.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "service/live_envelope.hpp"

using namespace pslam::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto envelope = DecodeLiveEnvelope(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!envelope) return 0;
  const LiveEnvelope& e = envelope.value();
  LiveState mirror("s-fuzz", 0.05);
  try {
    switch (e.kind) {
      case LiveEnvelope::Kind::kDelta: {
        mirror.Absorb(e.delta);
        const auto again = DecodeLiveEnvelope(EncodeDeltaEnvelope(e.node, e.seq, e.published_us, e.delta));
        if (!again || again.value().delta.tiles.size() != e.delta.tiles.size()) std::abort();
        break;
      }
      case LiveEnvelope::Kind::kKeyframe:
        mirror.Replace(e.snapshot, e.tiles);
        break;
      case LiveEnvelope::Kind::kEnd:
        break;
    }
  } catch (const std::exception&) {
  }
  (void)mirror.Snapshot();
  return 0;
}
