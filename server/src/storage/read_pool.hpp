#pragma once
// Read connections for the REST handlers. WAL lets them read while the writer commits; each lease
// is used by one thread at a time and goes back to the pool when released.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "storage/session_repository.hpp"
#include "storage/database.hpp"

namespace pslam::server {

class ReadPool {
 public:
  class Lease {
   public:
    Lease(ReadPool& pool, std::unique_ptr<Database> db) : pool_(pool), db_(std::move(db)), repository_(*db_) {}
    ~Lease() { pool_.Release(std::move(db_)); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    SessionRepository& repository() { return repository_; }

   private:
    ReadPool& pool_;
    std::unique_ptr<Database> db_;
    SessionRepository repository_;
  };

  explicit ReadPool(StorageLocation where) : where_(std::move(where)) {}
  // Throws StorageError if a new connection cannot be opened.
  std::unique_ptr<Lease> Acquire();

 private:
  void Release(std::unique_ptr<Database> db);

  StorageLocation where_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Database>> idle_;
};

}  // namespace pslam::server
