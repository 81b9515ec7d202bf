#include "service/json_views.hpp"

namespace pslam::server {

nlohmann::json ParseStoredJson(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  return j.is_object() ? j : nlohmann::json::object();
}

nlohmann::json SessionToJson(const SessionRow& row) {
  nlohmann::json j = {{"id", row.id},
                      {"name", row.name},
                      {"robot_id", row.robot_id},
                      {"source", row.source},
                      {"status", row.status},
                      {"created_at", row.created_at},
                      {"updated_at", row.updated_at},
                      {"closed_at", row.closed_at ? nlohmann::json(*row.closed_at) : nlohmann::json()},
                      {"laser", ParseStoredJson(row.laser_json)},
                      {"settings", ParseStoredJson(row.settings_json)},
                      {"last_seq", row.last_seq},
                      {"processed_seq", row.processed_seq},
                      {"scans", row.scans},
                      {"metrics", ParseStoredJson(row.metrics_json)}};
  j["replay_of"] = row.replay_of ? nlohmann::json(*row.replay_of) : nlohmann::json();
  j["failure"] = row.failure ? nlohmann::json(*row.failure) : nlohmann::json();
  return j;
}

nlohmann::json HypothesisToJson(const HypothesisRecord& h, bool with_cells) {
  nlohmann::json j = {{"id", h.id},
                      {"time", h.time},
                      {"target_cell", {h.target_cell.x, h.target_cell.y}},
                      {"reference_cell", {h.reference_cell.x, h.reference_cell.y}},
                      {"theta", h.theta},
                      {"translation", {h.translation_x, h.translation_y}},
                      {"psi", h.psi},
                      {"area", h.area},
                      {"cell_count", h.cells.size()},
                      {"status", h.status},
                      {"hit_ratio", h.hit_ratio},
                      {"psi_observed", h.psi_observed}};
  j["reference_map"] = h.reference_map ? nlohmann::json{{"site", h.reference_map->site}, {"version", h.reference_map->version}}
                                       : nlohmann::json();
  if (with_cells) {
    nlohmann::json cells = nlohmann::json::array();
    for (const PredictedCell& c : h.cells) cells.push_back({c.x, c.y, c.occupancy});
    j["cells"] = std::move(cells);
  }
  return j;
}

nlohmann::json TrajectoryToJson(const std::vector<TrajectoryRow>& rows) {
  nlohmann::json poses = nlohmann::json::array();
  for (const TrajectoryRow& r : rows) {
    poses.push_back({{"scan_index", r.scan_index}, {"seq", r.seq}, {"t", r.t}, {"x", r.x}, {"y", r.y}, {"theta", r.theta}});
  }
  return poses;
}

nlohmann::json EngineStatsToJson(const EngineStats& s) {
  nlohmann::json j = {{"processed_seq", s.processed_seq},
          {"scans", s.scans},
          {"updates", s.updates},
          {"resamplings", s.resamplings},
          {"particles", s.particles},
          {"neff", s.neff},
          {"scan_rate_hz", s.scan_rate_hz},
          {"latency_ms_mean", s.latency_ms_mean},
          {"latency_ms_max", s.latency_ms_max},
          {"step_ms_mean", s.step_ms_mean},
          {"queued", s.queued},
          {"rebuilding", s.rebuilding},
          {"tracking", s.tracking},
          {"tracking_reason", s.tracking_reason},
          {"targets", s.targets},
          {"predictions_made", s.predictions_made},
          {"hypotheses", s.hypotheses},
          {"prediction_ms_mean", s.prediction_ms_mean},
          {"prediction_ms_max", s.prediction_ms_max},
          {"updates_using_predictions", s.updates_using_predictions},
          {"exploration", s.exploration},
          {"exploration_reason", s.exploration_reason},
          {"mapped_m2", s.mapped_m2},
          {"predicted_m2", s.predicted_m2},
          {"predicted_frontiers", s.predicted_frontiers},
          {"mode", s.mode}};
  if (s.mode == "localize" || s.mode == "extend_localize") {
    const LocalizationStats& l = s.localization;
    j["localization"] = {{"localized", l.localized},
                         {"cluster_weight", l.cluster_weight},
                         {"position_std_m", l.position_std_m},
                         {"heading_std_rad", l.heading_std_rad},
                         {"clusters", l.clusters},
                         {"injected", l.injected},
                         {"place", l.place}};
  }
  return j;
}

nlohmann::json HypothesisCountsToJson(const HypothesisCounts& c) {
  return {{"accepted", c.accepted},
          {"pending", c.pending},
          {"confirmed", c.confirmed},
          {"refuted", c.refuted},
          {"expired", c.expired},
          {"mean_hit_ratio", c.mean_hit_ratio}};
}

nlohmann::json EventToJson(const EventRow& e) {
  return {{"id", e.id},
          {"session_id", e.session_id ? nlohmann::json(*e.session_id) : nlohmann::json()},
          {"t", e.t},
          {"kind", e.kind},
          {"detail", ParseStoredJson(e.detail_json)}};
}

nlohmann::json TargetToJson(const ExplorationTarget& t) {
  nlohmann::json path = nlohmann::json::array();
  for (const auto& p : t.path) path.push_back({p[0], p[1]});
  return {{"x", t.x}, {"y", t.y}, {"path", path}, {"pose", {{"x", t.pose_x}, {"y", t.pose_y}, {"theta", t.pose_theta}}}};
}

}  // namespace pslam::server
