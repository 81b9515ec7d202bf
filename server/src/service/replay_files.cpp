#include "service/replay_files.hpp"

#include <algorithm>

namespace pslam::server {
namespace {

std::string KindOf(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".clf" || ext == ".log") return "log";
  if (ext == ".relations") return "relations";
  if (ext == ".yaml" || ext == ".yml") return "reference_map";
  return {};
}

}  // namespace

std::vector<ReplayFile> ListReplayFiles(const std::filesystem::path& root, std::size_t max_files, int max_depth) {
  namespace fs = std::filesystem;
  const fs::path base = fs::canonical(root);
  std::vector<ReplayFile> files;
  fs::recursive_directory_iterator it(base, fs::directory_options::skip_permission_denied);
  for (; it != fs::recursive_directory_iterator() && files.size() < max_files; ++it) {
    const fs::path& path = it->path();
    const bool hidden = path.filename().string().starts_with(".");
    std::error_code ec;
    if (it->is_directory(ec)) {
      if (hidden || it.depth() >= max_depth) it.disable_recursion_pending();
      continue;
    }
    if (hidden || !it->is_regular_file(ec)) continue;
    const std::string kind = KindOf(path);
    if (kind.empty()) continue;
    // Replays resolve names the same way (ReplayService::ResolveInside): a link out is refused there.
    const fs::path real = fs::weakly_canonical(path, ec);
    if (ec) continue;
    const auto [root_end, unused] = std::mismatch(base.begin(), base.end(), real.begin(), real.end());
    if (root_end != base.end()) continue;
    files.push_back({path.lexically_relative(base).generic_string(), it->file_size(ec), kind});
  }
  std::sort(files.begin(), files.end(), [](const ReplayFile& a, const ReplayFile& b) { return a.name < b.name; });
  return files;
}

}  // namespace pslam::server
