#include "storage/database.hpp"

namespace pslam::server {

Database Database::Open(const StorageLocation& where, Mode mode) {
  return where.kind == StorageKind::kPostgres ? Connect(where.path_or_url)
                                              : Open(where.path_or_url, mode, where.sqlite_synchronous_full);
}

Transaction::Transaction(Database& db) : db_(db) { db_.Exec(db_.engine().BeginSql()); }

Transaction::~Transaction() {
  if (done_) return;
  try {
    db_.Exec("ROLLBACK");
  } catch (const StorageError&) {
    // The engine may already have rolled back after an error; nothing to undo.
  }
}

void Transaction::Commit() {
  db_.Exec("COMMIT");
  done_ = true;
}

Savepoint::Savepoint(Database& db) : db_(db) { db_.Exec("SAVEPOINT job"); }

Savepoint::~Savepoint() {
  if (done_) return;
  try {
    db_.Exec("ROLLBACK TO SAVEPOINT job");
    db_.Exec("RELEASE SAVEPOINT job");
  } catch (const StorageError&) {
  }
}

void Savepoint::Release() {
  db_.Exec("RELEASE SAVEPOINT job");
  done_ = true;
}

}  // namespace pslam::server
