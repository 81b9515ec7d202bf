#include "storage/storage_writer.hpp"

#include <algorithm>
#include <exception>
#include <future>
#include <iostream>
#include <vector>

#include "common/clock.hpp"
#include "storage/migrate.hpp"

namespace pslam::server {
namespace {
// Bounds a transaction's size so that one huge backlog does not hold the write lock for long.
constexpr std::size_t kMaxBatch = 1024;
}  // namespace

Result<std::unique_ptr<StorageWriter>> StorageWriter::Open(const StorageLocation& where) {
  try {
    Database db = Database::Open(where, Database::Mode::kReadWrite);
    const int version = ApplyMigrations(db, EmbeddedMigrations(where.kind));
    return std::unique_ptr<StorageWriter>(new StorageWriter(std::move(db), version));
  } catch (const std::exception& e) {
    return Error{e.what()};
  }
}

StorageWriter::StorageWriter(Database db, int schema_version)
    : db_(std::move(db)), repository_(db_), schema_version_(schema_version), thread_([this] { Loop(); }) {}

StorageWriter::~StorageWriter() { Stop(); }

bool StorageWriter::Submit(Job job, Done done) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    queue_.push_back({std::move(job), std::move(done)});
  }
  wake_.notify_one();
  return true;
}

void StorageWriter::Execute(Job job) {
  std::promise<void> committed;
  auto future = committed.get_future();
  auto failure = std::make_shared<std::exception_ptr>();
  const bool accepted = Submit(
      [job = std::move(job), failure](SessionRepository& repo) {
        try {
          job(repo);
        } catch (...) {
          *failure = std::current_exception();
          throw;
        }
      },
      [&committed, failure](bool ok, const std::string& error) {
        if (ok) {
          committed.set_value();
        } else if (*failure) {
          committed.set_exception(*failure);
        } else {
          committed.set_exception(std::make_exception_ptr(std::runtime_error(error)));
        }
      });
  if (!accepted) throw std::runtime_error("storage is shut down");
  future.get();
}

void StorageWriter::Stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return;
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
  try {
    // SQLite: fold the WAL into the database file, so a stopped server leaves one self-contained file.
    db_.engine().Checkpoint();
  } catch (const StorageError& e) {
    std::cerr << "storage: checkpoint at shutdown failed: " << e.what() << "\n";
  }
}

std::size_t StorageWriter::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

WriterStats StorageWriter::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

bool StorageWriter::RunAtOnce(std::vector<Pending>& batch) {
  try {
    Transaction tx(db_);
    for (Pending& p : batch) p.job(repository_);
    tx.Commit();
    return true;
  } catch (const std::exception&) {
    return false;  // rolled back; the jobs run again one by one to find the failing one
  }
}

void StorageWriter::RunOneByOne(std::vector<Pending>& batch, std::vector<std::string>& errors,
                                std::string& commit_error) {
  try {
    Transaction tx(db_);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      try {
        Savepoint savepoint(db_);
        batch[i].job(repository_);
        savepoint.Release();
      } catch (const std::exception& e) {
        errors[i] = e.what();
        if (errors[i].empty()) errors[i] = "storage job failed";
      }
    }
    tx.Commit();
  } catch (const std::exception& e) {
    commit_error = std::string("commit failed: ") + e.what();
    std::cerr << "storage: " << commit_error << "\n";
  }
}

void StorageWriter::Loop() {
  for (;;) {
    std::vector<Pending> batch;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and everything queued is committed
      while (!queue_.empty() && batch.size() < kMaxBatch) {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      }
    }
    const SteadyTime start = SteadyNow();
    std::vector<std::string> errors(batch.size());
    std::string commit_error;
    if (!RunAtOnce(batch)) RunOneByOne(batch, errors, commit_error);
    const double ms = SecondsSince(start) * 1e3;
    if (!commit_error.empty()) std::fill(errors.begin(), errors.end(), commit_error);  // nothing was kept
    const auto failed = static_cast<std::size_t>(
        std::count_if(errors.begin(), errors.end(), [](const std::string& e) { return !e.empty(); }));
    {
      std::lock_guard lock(mutex_);
      ++stats_.commits;
      stats_.jobs += batch.size();
      stats_.failed_jobs += failed;
      stats_.last_commit_ms = ms;
      stats_.max_commit_ms = std::max(stats_.max_commit_ms, ms);
    }
    // Counted before noted: whoever sees the failure (health reads it first) also sees it counted.
    const auto first_error = std::find_if(errors.begin(), errors.end(), [](const std::string& e) { return !e.empty(); });
    if (first_error != errors.end()) failures_.Note(*first_error);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      if (batch[i].done) batch[i].done(errors[i].empty(), errors[i]);
    }
  }
}

}  // namespace pslam::server
