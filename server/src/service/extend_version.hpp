#pragma once
// Extend mode's result: when an extend session closes, its final map becomes its site's next map
// version, recording the version it started from.
#include <optional>

#include "service/session_runtime.hpp"
#include "storage/records.hpp"

namespace pslam::server {

// The version row for a finished engine's final map; nullopt unless the session is in extend mode
// and got to map (it localized on the site's map). The caller stores it (its version is assigned
// then).
std::optional<SiteMapRow> ExtendedSiteMap(const SessionRuntime& rt);

}  // namespace pslam::server
