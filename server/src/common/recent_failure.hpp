#pragma once
// The latest failure of one kind (storage writes, engines) and when it happened, so /api/health can
// report a server that still answers but no longer does its work. Thread-safe.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "common/clock.hpp"

namespace pslam::server {

class RecentFailure {
 public:
  void Note(const std::string& what) {
    std::lock_guard lock(mutex_);
    last_ = SteadyNow();
    what_ = what.substr(0, 300);
    ++count_;
  }
  // "what (N so far)" of the latest failure if it happened less than 'window' ago.
  std::optional<std::string> Within(std::chrono::seconds window) const {
    std::lock_guard lock(mutex_);
    if (!last_ || SteadyNow() - *last_ > window) return std::nullopt;
    return what_ + " (" + std::to_string(count_) + " so far)";
  }

 private:
  mutable std::mutex mutex_;
  std::optional<SteadyTime> last_;
  std::string what_;
  std::uint64_t count_ = 0;
};

}  // namespace pslam::server
