// REST request targets: percent-decoding, the query string and the strict number parsers. Bad input
// must be nullopt or ApiError(400), never a crash or another exception.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "api/query.hpp"
#include "service/api_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)pslam::server::PercentDecode(text, true);
  const auto target = pslam::server::ParseTarget(text);
  if (!target) return 0;
  // The router relies on this: a decoded path or query never holds a NUL byte.
  if (target->path.find('\0') != std::string::npos) std::abort();
  for (const auto& [key, value] : target->query) {
    if (key.find('\0') != std::string::npos || value.find('\0') != std::string::npos) std::abort();
    try {
      (void)pslam::server::QueryNumber(target->query, key);
    } catch (const pslam::server::ApiError& e) {
      if (e.status() != 400) std::abort();
    }
    try {
      (void)pslam::server::QueryInteger(target->query, key, -1000, 1000);
    } catch (const pslam::server::ApiError& e) {
      if (e.status() != 400) std::abort();
    }
    try {
      (void)pslam::server::QueryString(target->query, key);
    } catch (const pslam::server::ApiError& e) {
      if (e.status() != 400) std::abort();
    }
  }
  return 0;
}
