#pragma once
// Minimal leveled logging to stderr for the agent process. One line per call, prefixed with the
// wall-clock time, so journald/systemd output and a developer's terminal read the same.
#include <sstream>
#include <string>

namespace pslam::agent {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
void LogLine(LogLevel level, const std::string& line);

// Usage: PSLAM_LOG(kInfo) << "connected to " << host;  The stream is built only if enabled.
class LogMessage {
 public:
  explicit LogMessage(LogLevel level) : level_(level) {}
  ~LogMessage() { LogLine(level_, stream_.str()); }
  LogMessage(const LogMessage&) = delete;
  LogMessage& operator=(const LogMessage&) = delete;
  std::ostringstream& stream() { return stream_; }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};

// Turns the streamed expression into void so that both branches of PSLAM_LOG's ?: agree (glog's
// trick; an if/else macro would capture a following else).
struct LogVoidify {
  void operator&(std::ostream&) {}
};

}  // namespace pslam::agent

#define PSLAM_LOG(level)                                                        \
  (::pslam::agent::LogLevel::level < ::pslam::agent::GetLogLevel())             \
      ? (void)0                                                                 \
      : ::pslam::agent::LogVoidify() & ::pslam::agent::LogMessage(::pslam::agent::LogLevel::level).stream()
