#pragma once
// What a replay may read: the files of the server's replay directory that a replay request can
// name, with their names as the request must give them (relative to the directory).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pslam::server {

struct ReplayFile {
  std::string name;       // relative to the replay directory, '/'-separated
  std::uintmax_t bytes = 0;
  std::string kind;       // "log" (.clf, .log), "relations" (.relations) or "reference_map" (.yaml)
};

// Regular files of those kinds under 'root', sorted by name, at most 'max_depth' folders deep and
// at most 'max_files' of them (a huge directory must not make a huge answer). Hidden files and
// folders, and links that leave 'root', are left out. Throws std::filesystem::filesystem_error when
// 'root' cannot be read.
std::vector<ReplayFile> ListReplayFiles(const std::filesystem::path& root, std::size_t max_files = 2000,
                                        int max_depth = 4);

}  // namespace pslam::server
