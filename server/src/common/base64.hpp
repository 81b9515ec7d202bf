#pragma once
// Base64 (RFC 4648, with padding): how JSON carries bytes (Foxglove's "contentEncoding": "base64").
#include <string>
#include <string_view>

namespace pslam::server {

std::string Base64Encode(std::string_view bytes);

}  // namespace pslam::server
