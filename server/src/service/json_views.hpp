#pragma once
// JSON views of stored and live records, shared by the REST handlers and the live view so both
// spell every field the same way (schema/openapi.yaml, schema/ws/live.md).
#include <nlohmann/json.hpp>

#include "engine/engine_output.hpp"
#include "model/hypothesis.hpp"
#include "storage/records.hpp"

namespace pslam::server {

nlohmann::json SessionToJson(const SessionRow& row);
// The hypothesis without its cells (a count instead) unless 'with_cells'.
nlohmann::json HypothesisToJson(const HypothesisRecord& h, bool with_cells);
nlohmann::json TrajectoryToJson(const std::vector<TrajectoryRow>& rows);
nlohmann::json EngineStatsToJson(const EngineStats& stats);
nlohmann::json HypothesisCountsToJson(const HypothesisCounts& counts);
nlohmann::json EventToJson(const EventRow& event);
nlohmann::json TargetToJson(const ExplorationTarget& target);
// Parses a JSON text stored by us; an object, or {} if it is not one.
nlohmann::json ParseStoredJson(const std::string& text);

}  // namespace pslam::server
