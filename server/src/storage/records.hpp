#pragma once
// Rows of the database as plain structs (see schema/db). The repository converts between these
// and SQL; nothing else knows the table layout.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/checkpoint.hpp"
#include "model/hypothesis.hpp"

namespace pslam::server {

struct SessionRow {
  std::string id;
  std::string name;
  std::string robot_id;
  std::string source = "agent";     // agent | api | replay
  std::optional<std::string> replay_of;
  std::string status = "active";    // active | closed | failed
  double created_at = 0.0;
  double updated_at = 0.0;
  std::optional<double> closed_at;
  std::string laser_json = "{}";
  std::string settings_json = "{}";
  std::int64_t last_seq = 0;        // highest stored input (read-only: derived from inputs)
  std::int64_t processed_seq = 0;
  std::int64_t scans = 0;
  std::string stats_json = "{}";
  std::string metrics_json = "{}";
  std::optional<std::string> failure;  // why a failed session failed
  std::int64_t rebuilds = 0;           // start-ups in a row that began rebuilding and did not complete ...
  std::int64_t rebuild_seq = 0;        // ... with this many stored inputs
};

struct SessionFilter {
  std::optional<std::string> status;
  std::optional<std::string> source;
  std::optional<std::string> robot_id;
  std::optional<std::string> name_contains;
  std::optional<double> created_after;
  std::optional<double> created_before;
  int limit = 50;
  int offset = 0;
};

struct SessionPage {
  std::vector<SessionRow> sessions;
  std::int64_t total = 0;
};

struct HypothesisStatusRow {
  std::int64_t hypothesis_id = 0;
  double t = 0.0;
  std::string status;
  double hit_ratio = 0.0;
  double psi_observed = 0.0;
};

struct HypothesisFilter {
  std::optional<std::string> status;
  std::optional<double> min_psi;
  std::optional<double> t_from, t_to;
  // World bounding box [min_x, min_y, max_x, max_y]: hypotheses whose cells' box intersects it.
  std::optional<std::array<double, 4>> bbox;
  int limit = 100;
  int offset = 0;
};

struct HypothesisPage {
  std::vector<HypothesisRecord> hypotheses;
  std::int64_t total = 0;
};

struct HypothesisCounts {
  std::int64_t accepted = 0, pending = 0, confirmed = 0, refuted = 0, expired = 0;
  double mean_hit_ratio = 0.0;                // over pending and confirmed hypotheses
};

struct EventRow {
  std::int64_t id = 0;
  std::optional<std::string> session_id;
  double t = 0.0;
  std::string kind;
  std::string detail_json = "{}";
};

struct SiteRow {
  std::string id;
  std::string name;
  double created_at = 0.0;
  std::int64_t versions = 0;        // read-only: derived from site_maps
  std::int64_t latest_version = 0;  // 0: no map yet
};

// One version of a site's map. 'yaml' and 'pgm' are left empty by listings.
struct SiteMapRow {
  std::string site_id;
  std::int64_t version = 0;
  double created_at = 0.0;
  std::string source = "import";    // session | import
  std::optional<std::string> session_id;
  std::optional<std::int64_t> extends_version;  // made by an extend session from this version
  std::string note;
  double resolution = 0.0;
  int width = 0, height = 0;
  double origin_x = 0.0, origin_y = 0.0;
  std::string yaml;
  std::string pgm;
};

}  // namespace pslam::server
