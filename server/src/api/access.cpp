#include "api/access.hpp"

namespace pslam::server {
namespace {

bool ConstantTimeEquals(std::string_view a, std::string_view b) {
  // The length may leak through timing; the content may not.
  if (a.size() != b.size() || b.empty()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

bool AnyMatches(const std::vector<std::string>& tokens, std::string_view token) {
  bool match = false;
  for (const std::string& t : tokens) match |= ConstantTimeEquals(token, t);  // no early exit
  return match;
}

}  // namespace

TokenAuth::TokenAuth(std::vector<std::string> agent_tokens, std::vector<std::string> viewer_tokens)
    : agent_tokens_(std::move(agent_tokens)), viewer_tokens_(std::move(viewer_tokens)) {}

Access TokenAuth::Check(std::string_view token) const {
  if (!enabled()) return Access::kWrite;
  if (token.empty()) return Access::kNone;
  if (AnyMatches(agent_tokens_, token)) return Access::kWrite;
  if (AnyMatches(viewer_tokens_, token)) return Access::kRead;
  return Access::kNone;
}

}  // namespace pslam::server
