#pragma once
// A fresh directory under the system temp dir, removed with everything in it at scope exit: what
// the tests of core, server and agent use for files of their own.
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>

namespace pslam::testing {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "pslam-test") {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            (prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace pslam::testing
