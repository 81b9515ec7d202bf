#pragma once
// Closes the agent's server session over REST (POST /api/sessions/{id}/close) once a replay is
// finished and acknowledged, so the server writes the final map and frees the session's slot.
#include <optional>
#include <string>

#include "link/server_link.hpp"

namespace pslam::agent {

// nullopt on success, else what went wrong. Waits at most 'timeout_s' (the server drains the
// session's filter before it answers).
std::optional<std::string> CloseServerSession(const ServerLinkOptions& link, const std::string& session_id,
                                              double timeout_s);

}  // namespace pslam::agent
