#include "net/static_files.hpp"

#include <fstream>
#include <map>
#include <sstream>

namespace pslam::server {
namespace fs = std::filesystem;
namespace {
constexpr std::uintmax_t kMaxFileBytes = 64ull << 20;
}  // namespace

StaticFiles::StaticFiles(std::optional<fs::path> root) {
  std::error_code ec;
  if (root) {
    const fs::path canonical = fs::canonical(*root, ec);
    if (!ec && fs::is_directory(canonical, ec)) root_ = canonical;
  }
}

std::string StaticFiles::ContentType(const fs::path& file) {
  static const std::map<std::string, std::string> kTypes = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"}, {".map", "application/json"}, {".svg", "image/svg+xml"},
      {".png", "image/png"}, {".jpg", "image/jpeg"}, {".jpeg", "image/jpeg"}, {".gif", "image/gif"},
      {".ico", "image/x-icon"}, {".webp", "image/webp"}, {".wasm", "application/wasm"},
      {".woff", "font/woff"}, {".woff2", "font/woff2"}, {".ttf", "font/ttf"}, {".txt", "text/plain; charset=utf-8"},
      {".webmanifest", "application/manifest+json"}};
  const auto it = kTypes.find(file.extension().string());
  return it == kTypes.end() ? "application/octet-stream" : it->second;
}

ApiResponse StaticFiles::Serve(const std::string& path, const std::string& if_none_match) const {
  if (!root_) return ErrorResponse(404, "not_found", "no web viewer is installed (see --web)");
  // Segment by segment: nothing that climbs, nothing hidden, nothing that is not a plain name.
  fs::path relative;
  std::stringstream in(path);
  std::string segment;
  while (std::getline(in, segment, '/')) {
    if (segment.empty()) continue;
    if (segment == "." || segment == ".." || segment.front() == '.' || segment.find('\\') != std::string::npos) {
      return ErrorResponse(404, "not_found", "no file " + path);
    }
    relative /= segment;
  }
  if (relative.empty()) relative = "index.html";
  std::error_code ec;
  fs::path file = fs::canonical(*root_ / relative, ec);
  const bool is_file = !ec && fs::is_regular_file(file, ec);
  if (!is_file) {
    // A client-side route (no extension) gets the app; a missing asset is a real 404.
    if (relative.has_extension()) return ErrorResponse(404, "not_found", "no file " + path);
    file = fs::canonical(*root_ / "index.html", ec);
    if (ec || !fs::is_regular_file(file, ec)) return ErrorResponse(404, "not_found", "no file " + path);
  }
  const auto [root_end, unused] = std::mismatch(root_->begin(), root_->end(), file.begin(), file.end());
  if (root_end != root_->end()) return ErrorResponse(404, "not_found", "no file " + path);  // a symlink out
  const auto size = fs::file_size(file, ec);
  if (ec || size > kMaxFileBytes) return ErrorResponse(404, "not_found", "no file " + path);
  const auto mtime = fs::last_write_time(file, ec).time_since_epoch().count();
  // Appended piece by piece: '"' + std::string&& trips GCC 12's false -Wrestrict warning.
  std::string etag(1, '"');
  etag += std::to_string(size) + "-" + std::to_string(mtime);
  etag += '"';

  ApiResponse r;
  r.content_type = ContentType(file);
  const fs::path served_relative = fs::relative(file, *root_, ec);
  const bool hashed_asset = !served_relative.empty() && *served_relative.begin() == "assets";
  r.headers.emplace_back("Cache-Control", hashed_asset ? "public, max-age=31536000, immutable" : "no-cache");
  r.headers.emplace_back("ETag", etag);
  r.headers.emplace_back("X-Content-Type-Options", "nosniff");
  if (!if_none_match.empty() && if_none_match == etag) {
    r.status = 304;
    return r;
  }
  std::ifstream stream(file, std::ios::binary);
  r.body.assign(std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>());
  if (!stream.good() && !stream.eof()) return ErrorResponse(500, "internal", "cannot read " + path);
  r.status = 200;
  return r;
}

}  // namespace pslam::server
