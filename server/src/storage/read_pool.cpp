#include "storage/read_pool.hpp"

namespace pslam::server {
namespace {
constexpr std::size_t kMaxIdle = 8;
}  // namespace

std::unique_ptr<ReadPool::Lease> ReadPool::Acquire() {
  std::unique_ptr<Database> db;
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      db = std::move(idle_.back());
      idle_.pop_back();
    }
  }
  if (!db) {
    db = std::make_unique<Database>(Database::Open(where_, Database::Mode::kReadWrite));
    // Read-write so SQLite's WAL shared memory works in every case, but refusing writes: readers only read.
    db->Exec(db->kind() == StorageKind::kSqlite ? "PRAGMA query_only = 1"
                                                : "SET SESSION CHARACTERISTICS AS TRANSACTION READ ONLY");
  }
  return std::make_unique<Lease>(*this, std::move(db));
}

void ReadPool::Release(std::unique_ptr<Database> db) {
  std::lock_guard lock(mutex_);
  if (idle_.size() < kMaxIdle) idle_.push_back(std::move(db));
}

}  // namespace pslam::server
