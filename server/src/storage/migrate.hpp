#pragma once
// Versioned schema migrations: schema/db/NNNN_description.sql for SQLite and
// schema/db/postgres/NNNN_description.sql for PostgreSQL (the same versions, each in its engine's
// dialect), compiled into the binary and applied in order at start-up. The database records the
// last one applied (SQLite: PRAGMA user_version; PostgreSQL: table schema_version); each migration
// runs in its own transaction together with that bump, so a crash mid-way leaves the database at
// the previous version, never in between.
#include <string>
#include <vector>

#include "storage/database.hpp"

namespace pslam::server {

struct Migration {
  int version = 0;
  std::string name;
  std::string sql;
};

// The migrations of schema/db for that engine (generated at build time).
const std::vector<Migration>& EmbeddedMigrations(StorageKind kind = StorageKind::kSqlite);

int SchemaVersion(Database& db);

// Applies every migration newer than the database's recorded version. Throws StorageError on a failed
// migration, and std::runtime_error if the database is newer than the migrations (a downgrade) or
// the versions are not 1, 2, 3, ... Returns the resulting version.
int ApplyMigrations(Database& db, const std::vector<Migration>& migrations);

}  // namespace pslam::server
