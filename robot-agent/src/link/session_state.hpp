#pragma once
// The server session this spool belongs to, kept beside the spool so that an agent restarted after
// a crash resumes its session instead of opening a new one (and the server, not the agent, decides
// what was already stored).
//
// Spool sequence numbers run forever; the wire's `seq` restarts at 1 per session. The mapping is
// wire seq = spool seq - seq_base, fixed when the session is created.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace pslam::agent {

struct SessionState {
  std::string session_id;
  std::uint64_t seq_base = 0;
};

// nullopt if the file does not exist or cannot be read (then a new session is started).
std::optional<SessionState> LoadSessionState(const std::filesystem::path& file);
// Atomic replace (write, fsync, rename). Throws std::runtime_error on failure.
void SaveSessionState(const std::filesystem::path& file, const SessionState& state);
void ClearSessionState(const std::filesystem::path& file);

// Where a log replay began in the spool (spool seq of its first event), kept beside the spool so
// that a restarted agent continues the log after what it already spooled instead of sending it
// again from the top: a replay emits the same events in the same order every time.
struct ReplayPosition {
  std::string log;
  std::uint64_t first_seq = 0;
};
std::optional<ReplayPosition> LoadReplayPosition(const std::filesystem::path& file);
void SaveReplayPosition(const std::filesystem::path& file, const ReplayPosition& position);  // atomic; throws

}  // namespace pslam::agent
