#pragma once
// The web viewer's files, from one directory. A request path is decoded, split into segments and
// refused if any segment is '..', '.', empty-with-meaning or hidden; the file is then looked up by
// its canonical path, which must stay inside the root (symlinks included). Hashed build assets
// (under assets/) are cached for a year, index.html is revalidated on every load.
#include <filesystem>
#include <optional>
#include <string>

#include "api/router.hpp"

namespace pslam::server {

class StaticFiles {
 public:
  // 'root' may be missing: every request then gets a 404 that says so.
  explicit StaticFiles(std::optional<std::filesystem::path> root);

  // GET or HEAD of 'path' (decoded, without the query). 'if_none_match' is the request's header.
  ApiResponse Serve(const std::string& path, const std::string& if_none_match) const;

  static std::string ContentType(const std::filesystem::path& file);

 private:
  std::optional<std::filesystem::path> root_;  // canonical
};

}  // namespace pslam::server
