#include "service/extend_version.hpp"

#include "common/clock.hpp"
#include "service/site_maps.hpp"

namespace pslam::server {

std::optional<SiteMapRow> ExtendedSiteMap(const SessionRuntime& rt) {
  if (rt.settings.mode != "extend") return std::nullopt;
  const auto frame = rt.engine->latest_frame();  // the final tick, published before Finish returned
  if (!frame || !frame->map || frame->stats.mode != "extend_map") return std::nullopt;
  SiteMapRow row = SessionSiteMap(rt.id, *frame->map);
  row.site_id = rt.settings.site;
  row.extends_version = rt.settings.map_version;
  row.note = "extends version " + std::to_string(rt.settings.map_version);
  row.created_at = UnixNow();
  return row;
}

}  // namespace pslam::server
