// P2OS serial bytes as the robot's line delivers them: the first byte sets the read size, the rest
// arrives in chunks of that size. Every framed packet goes through the decoders the client uses.
// Nothing may crash; a packet that comes out re-frames to bytes the parser accepts again.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "devices/p2os_protocol.hpp"

using namespace pslam::agent::p2os;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::span<const std::uint8_t> line(data + 1, size - 1);
  PacketParser parser;
  OdometryIntegrator odometry(ParamsForSubclass("p3dx-sh"));
  double time = 0.0;
  for (std::size_t i = 0; i < line.size(); i += chunk) {
    parser.Push(line.subspan(i, std::min(chunk, line.size() - i)), time += 0.01, 10.0 / 9600);
    if (i % 3 == 0 && data[0] & 0x80) parser.DiscardPartial();  // a read that timed out
    while (auto packet = parser.Next()) {
      if (packet->payload.empty() || packet->payload.size() > kMaxByteCount) std::abort();
      if (const auto sip = DecodeSip(packet->payload)) {
        (void)odometry.Update(*sip, packet->time);
        const auto again = DecodeSip(EncodeSipPayload(*sip));
        if (!again || again->x_pos != sip->x_pos || again->th_pos != sip->th_pos || again->sonar.size() != sip->sonar.size()) {
          std::abort();
        }
      }
      (void)DecodeCommand(packet->payload);
      if (const auto identity = ParseSync2Reply(packet->payload)) (void)ParamsForSubclass(identity->subclass);
      PacketParser reframe;
      reframe.Push(EncodePacket(packet->payload), 0.0);
      const auto same = reframe.Next();
      if (!same || same->payload != packet->payload) std::abort();
    }
  }
  return 0;
}
