#include "link/session_state.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "common/log.hpp"

namespace pslam::agent {

std::optional<SessionState> LoadSessionState(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    return SessionState{j.at("session_id").get<std::string>(), j.at("seq_base").get<std::uint64_t>()};
  } catch (const std::exception& e) {
    PSLAM_LOG(kWarning) << "ignoring unreadable session state " << file << ": " << e.what();
    return std::nullopt;
  }
}

void SaveSessionState(const std::filesystem::path& file, const SessionState& state) {
  const std::string text = nlohmann::json{{"session_id", state.session_id}, {"seq_base", state.seq_base}}.dump() + "\n";
  const std::filesystem::path tmp = file.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp.string());
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) throw std::runtime_error("cannot write " + tmp.string());
  std::filesystem::rename(tmp, file);
}

void ClearSessionState(const std::filesystem::path& file) {
  std::error_code ec;
  std::filesystem::remove(file, ec);
}

}  // namespace pslam::agent
