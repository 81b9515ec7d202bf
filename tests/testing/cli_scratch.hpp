#pragma once
// The real `pslam` binary run in a scratch directory of its own, removed afterwards: what the
// command-line tests of core share.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "testing/temp_dir.hpp"

namespace pslam::testing {

class CliScratch {
 public:
  explicit CliScratch(const std::string& name) : dir_("pslam-" + name) {}

  const std::filesystem::path& dir() const { return dir_.path(); }
  std::string Path(const std::string& name) const { return (dir() / name).string(); }

  // Exit status of `pslam COMMAND ARGS`, with its stdout and stderr kept in out.txt and err.txt.
  int Run(const std::string& command, const std::string& args) const {
    const std::string line = std::string(PSLAM_CLI_BINARY) + " " + command + " " + args + " >" + Path("out.txt") +
                             " 2>" + Path("err.txt");
    const int status = std::system(line.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string Read(const std::string& name) const {
    std::ifstream in(dir() / name);
    return {std::istreambuf_iterator<char>(in), {}};
  }

 private:
  TempDir dir_;
};

}  // namespace pslam::testing
