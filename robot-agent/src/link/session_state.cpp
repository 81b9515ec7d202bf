#include "link/session_state.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "common/log.hpp"
#include "link/json_sequence.hpp"

namespace pslam::agent {
namespace {

// Write, fsync, rename: a crash leaves the old file or the new one, never half of one.
void WriteAtomically(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp.string());
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) throw std::runtime_error("cannot write " + tmp.string());
  std::filesystem::rename(tmp, file);
}

}  // namespace

std::optional<SessionState> LoadSessionState(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    return SessionState{j.at("session_id").get<std::string>(), SequenceField(j, "seq_base")};
  } catch (const std::exception& e) {
    PSLAM_LOG(kWarning) << "ignoring unreadable session state " << file << ": " << e.what();
    return std::nullopt;
  }
}

void SaveSessionState(const std::filesystem::path& file, const SessionState& state) {
  WriteAtomically(file, nlohmann::json{{"session_id", state.session_id}, {"seq_base", state.seq_base}}.dump() + "\n");
}

void ClearSessionState(const std::filesystem::path& file) {
  std::error_code ec;
  std::filesystem::remove(file, ec);
}

std::optional<ReplayPosition> LoadReplayPosition(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    return ReplayPosition{j.at("log").get<std::string>(), SequenceField(j, "first_seq")};
  } catch (const std::exception& e) {
    PSLAM_LOG(kWarning) << "ignoring unreadable replay position " << file << ": " << e.what();
    return std::nullopt;
  }
}

void SaveReplayPosition(const std::filesystem::path& file, const ReplayPosition& position) {
  WriteAtomically(file, nlohmann::json{{"log", position.log}, {"first_seq", position.first_seq}}.dump() + "\n");
}

}  // namespace pslam::agent
