#pragma once
// Recorded data sets live beside the project (../shared/data), never inside it. A test that needs
// one skips with a clear message in a user's clone without them, and fails under CI=true.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace pslam::testing {

inline std::filesystem::path SharedDataDir() {
  if (const char* env = std::getenv("PSLAM_DATA_DIR")) return env;
  return PSLAM_SHARED_DATA_DIR;
}

inline bool RunningInCi() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

}  // namespace pslam::testing

// Resolves `relative` under the shared data dir into `var`, or skips (fails under CI) the test.
#define PSLAM_REQUIRE_DATA(var, relative)                                                          \
  const std::filesystem::path var = ::pslam::testing::SharedDataDir() / (relative);                \
  if (!std::filesystem::exists(var)) {                                                             \
    if (::pslam::testing::RunningInCi()) FAIL() << "data set missing under CI: " << var;          \
    GTEST_SKIP() << "data set not found: " << var << " (set PSLAM_DATA_DIR to the shared data)"; \
  }
