#pragma once
// Rate limit for live ticks: 'rate' tokens per second on average, at most 'capacity' saved up.
// A fixed spacing would hold a scan that follows the previous tick closely until the next period;
// with a small burst allowance the engine can publish every scan right after it is processed and
// still averages no more than 'rate' ticks per second.
#include <algorithm>
#include <chrono>

#include "common/clock.hpp"

namespace pslam::server {

class TokenBucket {
 public:
  TokenBucket(double rate_per_second, double capacity, SteadyTime now)
      : rate_(rate_per_second), capacity_(std::max(1.0, capacity)), tokens_(capacity_), updated_(now) {}

  // Takes a token if one is available at 'now'.
  bool TryTake(SteadyTime now) {
    Refill(now);
    if (tokens_ < 1.0 - kSlack) return false;
    tokens_ -= 1.0;
    return true;
  }

  // When the next token will be available (now or in the past when one is).
  SteadyTime NextToken(SteadyTime now) {
    Refill(now);
    if (tokens_ >= 1.0 - kSlack) return now;
    return now + std::chrono::duration_cast<SteadyTime::duration>(std::chrono::duration<double>((1.0 - tokens_) / rate_));
  }

 private:
  void Refill(SteadyTime now) {
    if (now <= updated_) return;
    tokens_ = std::min(capacity_, tokens_ + std::chrono::duration<double>(now - updated_).count() * rate_);
    updated_ = now;
  }

  static constexpr double kSlack = 1e-9;  // so the refill's rounding never costs a whole period

  double rate_;
  double capacity_;
  double tokens_;
  SteadyTime updated_;
};

}  // namespace pslam::server
