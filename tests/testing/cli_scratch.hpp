#pragma once
// The real `pslam` binary run in a scratch directory of its own, removed afterwards: what the
// command-line tests of core share.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace pslam::testing {

class CliScratch {
 public:
  explicit CliScratch(const std::string& name)
      : dir_(std::filesystem::temp_directory_path() / ("pslam-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
  }
  ~CliScratch() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  CliScratch(const CliScratch&) = delete;
  CliScratch& operator=(const CliScratch&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  // Exit status of `pslam COMMAND ARGS`, with its stdout and stderr kept in out.txt and err.txt.
  int Run(const std::string& command, const std::string& args) const {
    const std::string line = std::string(PSLAM_CLI_BINARY) + " " + command + " " + args + " >" + Path("out.txt") +
                             " 2>" + Path("err.txt");
    const int status = std::system(line.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string Read(const std::string& name) const {
    std::ifstream in(dir_ / name);
    return {std::istreambuf_iterator<char>(in), {}};
  }

 private:
  std::filesystem::path dir_;
};

}  // namespace pslam::testing
