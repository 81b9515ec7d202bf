// What reaches the agent from outside: the server's text messages (welcome, ack, target, error,
// redirect) and the records of its spool file on disk. Any bytes must give a message or a clear
// "unknown", never a crash; a target that parses has a bounded turn, and a record that decodes
// encodes back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <span>
#include <string_view>
#include <variant>

#include "link/messages.hpp"

using namespace pslam::agent;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ServerMessage message = ParseServerMessage(std::string_view(reinterpret_cast<const char*>(data), size));
  if (const auto* target = std::get_if<TargetMessage>(&message)) {
    if (!(target->turn >= 0.0 && target->turn <= 4.0 * std::numbers::pi)) std::abort();
  }
  const std::span<const std::uint8_t> record(data, size);
  if (const auto decoded = DecodeRecord(record)) {
    const auto again = EncodeRecord(*decoded);
    if (again.size() != size) std::abort();
  }
  return 0;
}
