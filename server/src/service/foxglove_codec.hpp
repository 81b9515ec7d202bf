#pragma once
// The Foxglove WebSocket protocol's data, without the network (schema/ws/foxglove.md): the topics
// a running session offers, their JSON Schemas, JSON payloads in Foxglove's well-known schemas
// (so the stock 3D panel draws them), and the binary message-data frame header.
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "model/engine_stats.hpp"
#include "model/hypothesis.hpp"
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::server {

enum class FoxgloveTopic {
  kMap, kRobot, kScan, kTrajectory, kParticles, kTransform, kStats, kExploration, kPrediction
};
inline constexpr std::array kFoxgloveTopics = {FoxgloveTopic::kMap,        FoxgloveTopic::kRobot,
                                               FoxgloveTopic::kScan,       FoxgloveTopic::kTrajectory,
                                               FoxgloveTopic::kParticles,  FoxgloveTopic::kTransform,
                                               FoxgloveTopic::kStats,      FoxgloveTopic::kExploration,
                                               FoxgloveTopic::kPrediction};

inline constexpr const char* kFoxgloveMapFrame = "map";
// Grids are coarsened (by a whole factor) to at most this many cells per message: Foxglove has no
// grid deltas, each message carries the whole map.
inline constexpr std::size_t kFoxgloveMaxGridCells = 512 * 512;
inline constexpr std::size_t kFoxgloveMaxPoses = 1000;  // trajectory messages keep every k-th pose

struct FoxgloveTopicInfo {
  const char* suffix;       // the topic is "/<session id>/<suffix>"
  const char* schema_name;  // foxglove.* names are the well-known schemas the stock panels draw
};
FoxgloveTopicInfo TopicInfo(FoxgloveTopic topic);
// The topic's JSON Schema (schemaEncoding "jsonschema"), as text.
const std::string& TopicSchema(FoxgloveTopic topic);
// The robot's frame in a session ("<session id>/base_link"); every session's map frame is "map".
std::string RobotFrame(const std::string& session_id);

// One advertised channel, as the advertise message lists it.
nlohmann::json ChannelJson(std::uint32_t id, const std::string& session_id, FoxgloveTopic topic);

// Message data (opcode 0x01): this 13-byte header, then the payload.
inline constexpr std::size_t kFoxgloveMessageHeader = 13;
std::array<std::uint8_t, kFoxgloveMessageHeader> MessageDataHeader(std::uint32_t subscription, std::uint64_t ns);

// foxglove.Grid of the known part of 'grid', coarsened to at most 'max_cells' cells (a block keeps
// its most occupied known cell). Each cell is 3 bytes: "occupancy" (u8, percent 0..100, 255
// unknown: the live view's tile encoding), then a grey shade as red, green and blue, then alpha
// (0 for unknown), so the panel draws it as a map without settings.
std::string GridPayload(const OccupancyGrid& grid, std::uint64_t ns, std::size_t max_cells = kFoxgloveMaxGridCells);
// foxglove.Grid of the pending predictions' cells over their bounding box, coarsened like the map
// (a predicted wall wins its block): RGBA, walls orange-red and opaque, predicted free space a light
// blue wash, unpredicted cells transparent; "psi" (u8, offset 4) is the prediction's Ψ in percent.
std::string PredictionPayload(const std::vector<const HypothesisRecord*>& hypotheses, double resolution,
                              std::uint64_t ns, std::size_t max_cells = kFoxgloveMaxGridCells);
std::string PoseInFramePayload(const Pose2D& pose, std::uint64_t ns);
std::string TransformPayload(const std::string& session_id, const Pose2D& robot, std::uint64_t ns);
// The scan in the map frame: its origin is the sensor's pose, 'robot' * the scan's sensor offset.
std::string LaserScanPayload(const LaserScan& scan, const Pose2D& robot, std::uint64_t ns);
std::string PosesInFramePayload(std::span<const Pose2D> poses, std::uint64_t ns, std::size_t max_poses);
std::string StatsPayload(const EngineStats& stats);
// foxglove.SceneUpdate: frontiers as small spheres, the target as a larger one, the path as a line.
std::string ExplorationPayload(const std::vector<std::array<double, 2>>& frontiers,
                               const std::optional<ExplorationTarget>& target, std::uint64_t ns);

}  // namespace pslam::server
