#pragma once
// Versioned schema migrations: schema/db/NNNN_description.sql, compiled into the binary and
// applied in order at start-up. PRAGMA user_version records the last one applied; each migration
// runs in its own transaction together with the user_version bump, so a crash mid-way leaves the
// database at the previous version, never in between.
#include <string>
#include <vector>

#include "storage/sqlite.hpp"

namespace pslam::server {

struct Migration {
  int version = 0;
  std::string name;
  std::string sql;
};

// The migrations of schema/db (generated at build time).
const std::vector<Migration>& EmbeddedMigrations();

int SchemaVersion(Database& db);

// Applies every migration newer than the database's user_version. Throws SqliteError on a failed
// migration, and std::runtime_error if the database is newer than the migrations (a downgrade) or
// the versions are not 1, 2, 3, ... Returns the resulting version.
int ApplyMigrations(Database& db, const std::vector<Migration>& migrations);

}  // namespace pslam::server
