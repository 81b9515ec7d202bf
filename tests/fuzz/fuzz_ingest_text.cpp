// Ingest text frames as one connection sends them: one message per line, the first decoded before
// any hello, the rest with the laser of the last accepted hello. Every message must decode to a
// hello, an input or an IngestError; nothing may throw or crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <variant>

#include "service/api_error.hpp"
#include "service/ingest_codec.hpp"

using namespace pslam::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  const SettingsLimits limits;
  std::optional<LaserGeometry> laser;
  while (!rest.empty()) {
    const std::size_t eol = rest.find('\n');
    const std::string_view frame = rest.substr(0, eol);
    rest = eol == std::string_view::npos ? std::string_view() : rest.substr(eol + 1);
    const IngestMessage message = DecodeTextMessage(frame, laser ? &*laser : nullptr, limits);
    if (const auto* hello = std::get_if<HelloMessage>(&message)) {
      if (hello->laser) laser = hello->laser;
      // hello.settings is parsed later, against the server defaults; do it here too.
      try {
        (void)ParseSessionSettings(hello->settings, SessionSettings{}, limits);
      } catch (const ApiError&) {
      }
    } else if (const auto* input = std::get_if<InputRecord>(&message)) {
      // An accepted scan has exactly the laser's beam count and only finite, non-negative ranges.
      if (input->kind == InputKind::kScan && input->ranges.size() != static_cast<std::size_t>(laser->beams)) std::abort();
      for (float r : input->ranges) {
        if (r < 0.0f || std::isinf(r)) std::abort();
      }
      // The binary form of an accepted scan decodes to the same scan.
      if (input->kind == InputKind::kScan) {
        const std::string binary = EncodeBinaryScan(*input);
        const auto again = DecodeBinaryScan({reinterpret_cast<const std::uint8_t*>(binary.data()), binary.size()}, &*laser);
        const auto* same = std::get_if<InputRecord>(&again);
        if (!same || same->seq != input->seq || same->ranges.size() != input->ranges.size()) std::abort();
      }
    } else {
      (void)ErrorMessage(std::get<IngestError>(message).code, std::get<IngestError>(message).message);
    }
  }
  return 0;
}
