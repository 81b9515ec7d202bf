#include "storage/migrate.hpp"

#include <stdexcept>

namespace pslam::server {

int SchemaVersion(Database& db) { return db.engine().SchemaVersion(); }

int ApplyMigrations(Database& db, const std::vector<Migration>& migrations) {
  for (std::size_t i = 0; i < migrations.size(); ++i) {
    if (migrations[i].version != static_cast<int>(i) + 1) {
      throw std::runtime_error("migration " + migrations[i].name + " is out of sequence: expected version " +
                               std::to_string(i + 1));
    }
  }
  int version = SchemaVersion(db);
  if (version > static_cast<int>(migrations.size())) {
    throw std::runtime_error("database schema version " + std::to_string(version) +
                             " is newer than this server knows (" + std::to_string(migrations.size()) + ")");
  }
  for (const Migration& m : migrations) {
    if (m.version <= version) continue;
    Transaction tx(db);
    db.Exec(m.sql);
    db.engine().SetSchemaVersion(m.version);
    tx.Commit();
    version = m.version;
  }
  return version;
}

}  // namespace pslam::server
