#pragma once
// The single writer of the database, on its own thread (SQLite has one writer at a time, a
// PostgreSQL round trip costs time, and slow commits must never stall the network threads). Jobs queue up while a commit is in progress and
// the next batch runs in one transaction: group commit, so one fsync acknowledges many inputs.
// A failing job does not take its batch down with it: the batch is then rolled back and run again
// with each job in its own savepoint. (Savepoints for every job would cost PostgreSQL two more
// round trips per job.) Jobs must therefore be safe to run twice: they only write rows.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/recent_failure.hpp"
#include "common/result.hpp"
#include "storage/session_repository.hpp"
#include "storage/database.hpp"

namespace pslam::server {

struct WriterStats {
  std::uint64_t commits = 0;
  std::uint64_t jobs = 0;
  std::uint64_t failed_jobs = 0;
  double last_commit_ms = 0.0;
  double max_commit_ms = 0.0;
};

class StorageWriter {
 public:
  using Job = std::function<void(SessionRepository&)>;
  // Called on the writer thread once the job's transaction has committed (ok) or the job failed.
  using Done = std::function<void(bool ok, const std::string& error)>;

  // Opens (a SQLite file is created) the database, applies the migrations and starts the thread.
  static Result<std::unique_ptr<StorageWriter>> Open(const StorageLocation& where);
  ~StorageWriter();
  StorageWriter(const StorageWriter&) = delete;
  StorageWriter& operator=(const StorageWriter&) = delete;

  // Queues 'job'; false (and 'done' is never called) once the writer is stopping.
  bool Submit(Job job, Done done = {});
  // Runs 'job' and waits for its commit; rethrows what the job threw. Not for network threads.
  void Execute(Job job);
  // Commits everything queued, checkpoints the WAL into the main file and stops the thread.
  void Stop();

  int schema_version() const { return schema_version_; }
  std::size_t queued() const;
  WriterStats stats() const;
  const RecentFailure& failures() const { return failures_; }

 private:
  struct Pending {
    Job job;
    Done done;
  };
  StorageWriter(Database db, int schema_version);
  void Loop();
  // The batch in one transaction; false (rolled back) if a job or the commit failed.
  bool RunAtOnce(std::vector<Pending>& batch);
  // Each job in its own savepoint; 'errors' per job, or 'commit_error' for all.
  void RunOneByOne(std::vector<Pending>& batch, std::vector<std::string>& errors, std::string& commit_error);

  Database db_;
  SessionRepository repository_;
  int schema_version_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Pending> queue_;
  bool stopping_ = false;
  WriterStats stats_;
  RecentFailure failures_;
  std::thread thread_;
};

}  // namespace pslam::server
