#pragma once
// Replays: a stored session's raw inputs, or a CARMEN log from the server's replay directory, run
// through a fresh engine as a new session with its own settings, as fast as possible or at N times
// real time. Runs of the same data with different settings (or the same seed) can be compared;
// with a relations file or a reference map the finished session carries RPE and KL metrics.
#include <nlohmann/json.hpp>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "service/mapping_service.hpp"
#include "service/replay_files.hpp"

namespace pslam::server {

class ReplayService {
 public:
  // 'replay_dir': where logs, relations files and reference maps may be read; none: log replays
  // are refused.
  ReplayService(MappingService& mapping, std::optional<std::filesystem::path> replay_dir);
  ~ReplayService();
  ReplayService(const ReplayService&) = delete;
  ReplayService& operator=(const ReplayService&) = delete;

  // Validates the request (schema/openapi.yaml, ReplayRequest), creates the session and starts
  // feeding it on a thread of its own. Throws ApiError on bad requests.
  SessionRow Start(const nlohmann::json& body);
  // The replay directory's logs, relations files and reference maps; throws ApiError 403 without a
  // replay directory, 503 when it cannot be read.
  std::vector<ReplayFile> Files() const;
  // Stops the feeders; their sessions stay active and are closed after the next start.
  void Shutdown();

  // The canonical path of 'relative' inside 'root'; throws ApiError 400 if it leaves 'root' or is
  // absolute, 404 if it does not exist. Visible for testing.
  static std::filesystem::path ResolveInside(const std::filesystem::path& root, const std::string& relative);

 private:
  struct Plan;
  void Feed(std::shared_ptr<Plan> plan);
  void FeedStoredSession(Plan& plan);
  void FeedCarmenLog(Plan& plan);
  bool Pace(Plan& plan, double t);
  void ComputeMetrics(const Plan& plan);

  MappingService& mapping_;
  std::optional<std::filesystem::path> replay_dir_;
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::vector<std::thread> feeders_;
};

}  // namespace pslam::server
