#pragma once
// Base64 (RFC 4648, with padding): how JSON carries bytes (Foxglove's "contentEncoding": "base64").
#include <optional>
#include <string>
#include <string_view>

namespace pslam::server {

std::string Base64Encode(std::string_view bytes);
// nullopt unless 'text' is padded base64 of the standard alphabet (no whitespace).
std::optional<std::string> Base64Decode(std::string_view text);

}  // namespace pslam::server
