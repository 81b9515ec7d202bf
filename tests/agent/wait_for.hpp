#pragma once
// Polls 'condition' until it holds or 'timeout_s' passes; returns its last value.
#include <chrono>
#include <thread>

namespace pslam::agent::testing {

template <typename Condition>
bool WaitFor(Condition condition, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

}  // namespace pslam::agent::testing
