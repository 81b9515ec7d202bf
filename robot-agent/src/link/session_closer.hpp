#pragma once
// Closes the agent's server session over REST (POST /api/sessions/{id}/close) once a replay is
// finished and acknowledged, so the server writes the final map and frees the session's slot.
#include <optional>
#include <string>

#include "link/server_link.hpp"

namespace pslam::agent {

// nullopt on success, else what went wrong. A fleet's node that does not run the session answers
// 307 with the node that does; a node that cannot be reached is followed by the next one known. Waits at most 'timeout_s' (the server drains the
// session's filter before it answers).
std::optional<std::string> CloseServerSession(const ServerLinkOptions& link, const std::string& session_id,
                                              double timeout_s);

}  // namespace pslam::agent
