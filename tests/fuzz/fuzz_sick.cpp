// LMS-200 serial bytes in both directions: the first byte sets the read size and the measuring
// mode, the rest arrives in chunks. Every telegram found goes through DecodeScan. Nothing may
// crash; a telegram that comes out re-encodes to bytes the parser accepts again.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "devices/sick_protocol.hpp"

using namespace pslam::agent::sick;

namespace {

void Drain(TelegramParser& parser, bool replies, std::uint8_t measuring_mode) {
  while (auto t = parser.Next()) {
    if (t->data.size() > kMaxTelegram) std::abort();
    if (const auto scan = DecodeScan(*t, measuring_mode)) {
      if (scan->ranges_m.size() > 1023) std::abort();
    }
    std::vector<std::uint8_t> body{t->command};
    body.insert(body.end(), t->data.begin(), t->data.end());
    if (replies) body.push_back(t->status);
    TelegramParser reparse(replies);
    reparse.Push(EncodeTelegram(t->address, body), 0.0);
    const auto same = reparse.Next();
    if (!same || same->command != t->command || same->data != t->data || same->status != t->status) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t chunk = 1 + data[0] % 32;
  const std::uint8_t measuring_mode = data[0] >> 5;  // 0..7, the modes of §6.2
  const std::span<const std::uint8_t> line(data + 1, size - 1);
  TelegramParser from_scanner(true), to_scanner(false);
  double time = 0.0;
  for (std::size_t i = 0; i < line.size(); i += chunk) {
    const auto bytes = line.subspan(i, std::min(chunk, line.size() - i));
    time += 0.01;
    from_scanner.Push(bytes, time, 10.0 / 500000);
    to_scanner.Push(bytes, time);
    Drain(from_scanner, true, measuring_mode);
    Drain(to_scanner, false, measuring_mode);
  }
  return 0;
}
