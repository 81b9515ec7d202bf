#pragma once
// Who may do what: agents hold write tokens (ingest, create, close, delete, replay), viewers read
// tokens (everything that only reads). A write token also reads.
#include <string>
#include <string_view>
#include <vector>

namespace pslam::server {

enum class Access { kNone = 0, kRead = 1, kWrite = 2 };

class TokenAuth {
 public:
  TokenAuth(std::vector<std::string> agent_tokens, std::vector<std::string> viewer_tokens);

  // Without tokens configured (a loopback-only server) everyone has write access.
  bool enabled() const { return !agent_tokens_.empty() || !viewer_tokens_.empty(); }
  // The access 'token' grants (empty: none given). Compares in constant time, so response timing
  // does not reveal how much of a token was right.
  Access Check(std::string_view token) const;

 private:
  std::vector<std::string> agent_tokens_;
  std::vector<std::string> viewer_tokens_;
};

}  // namespace pslam::server
