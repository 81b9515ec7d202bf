#pragma once
// One SQL interface over the two storage engines: SQLite (embedded, the default) and PostgreSQL
// (a fleet's shared database). Every return code is checked; failures throw StorageError with the
// statement and the engine's message. Values are always bound, never spliced into SQL text, and
// placeholders are written '?' for both engines.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pslam::server {

class StorageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class StorageKind { kSqlite, kPostgres };

// Where a server keeps its data: a SQLite file, or a PostgreSQL connection URL.
struct StorageLocation {
  StorageKind kind = StorageKind::kSqlite;
  std::string path_or_url;
  // SQLite only: fsync the WAL on every commit, so an acknowledged commit survives a power loss
  // too; NORMAL survives a crash of the process (kill -9) but not of the machine. PostgreSQL's
  // commits are durable by its own synchronous_commit.
  bool sqlite_synchronous_full = true;
};

// What an engine implements; used through Statement and Database.
class StatementEngine {
 public:
  virtual ~StatementEngine() = default;
  virtual void Bind(int index, std::int64_t value) = 0;
  virtual void Bind(int index, double value) = 0;
  virtual void Bind(int index, std::string_view text) = 0;
  virtual void Bind(int index, std::span<const std::uint8_t> blob) = 0;
  virtual void BindNull(int index) = 0;
  virtual bool Step() = 0;
  virtual void Reset() = 0;
  virtual bool IsNull(int column) const = 0;
  virtual std::int64_t Int64(int column) const = 0;
  virtual double Double(int column) const = 0;
  virtual std::string Text(int column) const = 0;
  virtual std::vector<std::uint8_t> Blob(int column) const = 0;
};

class DatabaseEngine {
 public:
  virtual ~DatabaseEngine() = default;
  virtual StorageKind kind() const = 0;
  virtual void Exec(std::string_view sql) = 0;
  virtual std::unique_ptr<StatementEngine> Prepare(std::string_view sql) = 0;
  // Rows changed by the last INSERT, UPDATE or DELETE.
  virtual int Changes() const = 0;
  // The statement that opens a write transaction.
  virtual const char* BeginSql() const = 0;
  // The last migration applied, and recording a new one (inside the migration's transaction).
  virtual int SchemaVersion() = 0;
  virtual void SetSchemaVersion(int version) = 0;
  // Called once by the writer at shutdown (SQLite folds its WAL into the main file).
  virtual void Checkpoint() {}
};

class Statement {
 public:
  explicit Statement(std::unique_ptr<StatementEngine> engine) : engine_(std::move(engine)) {}

  // Binds parameter 'index' (1-based).
  Statement& Bind(int index, std::int64_t value) { return engine_->Bind(index, value), *this; }
  Statement& Bind(int index, int value) { return Bind(index, static_cast<std::int64_t>(value)); }
  Statement& Bind(int index, double value) { return engine_->Bind(index, value), *this; }
  Statement& Bind(int index, std::string_view text) { return engine_->Bind(index, text), *this; }
  Statement& Bind(int index, const char* text) { return Bind(index, std::string_view(text)); }
  Statement& Bind(int index, const std::string& text) { return Bind(index, std::string_view(text)); }
  Statement& Bind(int index, std::span<const std::uint8_t> blob) { return engine_->Bind(index, blob), *this; }
  Statement& Bind(int index, std::nullptr_t) { return engine_->BindNull(index), *this; }
  template <typename T>
  Statement& Bind(int index, const std::optional<T>& value) {
    return value ? Bind(index, *value) : Bind(index, nullptr);
  }
  // Binds the arguments to parameters 1, 2, ...
  template <typename... Args>
  Statement& BindAll(const Args&... args) {
    int index = 0;
    (Bind(++index, args), ...);
    return *this;
  }

  // Advances to the next row: true if there is one, false when done.
  bool Step() { return engine_->Step(); }
  // Steps a statement that returns no rows.
  void Run() {
    while (Step()) {
    }
  }
  // Ready to run again with new bindings.
  void Reset() { engine_->Reset(); }

  bool IsNull(int column) const { return engine_->IsNull(column); }
  std::int64_t Int64(int column) const { return engine_->Int64(column); }
  int Int(int column) const { return static_cast<int>(Int64(column)); }
  double Double(int column) const { return engine_->Double(column); }
  std::string Text(int column) const { return engine_->Text(column); }
  std::vector<std::uint8_t> Blob(int column) const { return engine_->Blob(column); }

 private:
  std::unique_ptr<StatementEngine> engine_;
};

class Database {
 public:
  enum class Mode { kReadWrite, kReadOnly };
  // A SQLite file, opened (created in read-write mode) in WAL mode with foreign keys on.
  static Database Open(const std::string& path, Mode mode, bool synchronous_full = true);
  // A PostgreSQL database, e.g. "postgresql://user@127.0.0.1:5432/pslam".
  static Database Connect(const std::string& url);
  // Either, as 'where' says.
  static Database Open(const StorageLocation& where, Mode mode);

  explicit Database(std::unique_ptr<DatabaseEngine> engine) : engine_(std::move(engine)) {}

  StorageKind kind() const { return engine_->kind(); }
  // Runs one or more statements without parameters (schema scripts, pragmas).
  void Exec(std::string_view sql) { engine_->Exec(sql); }
  Statement Prepare(std::string_view sql) { return Statement(engine_->Prepare(sql)); }
  int Changes() const { return engine_->Changes(); }
  DatabaseEngine& engine() { return *engine_; }

 private:
  std::unique_ptr<DatabaseEngine> engine_;
};

// BEGIN ... COMMIT (SQLite: BEGIN IMMEDIATE); rolls back unless Commit() was called.
class Transaction {
 public:
  explicit Transaction(Database& db);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void Commit();

 private:
  Database& db_;
  bool done_ = false;
};

// A nested unit inside a transaction: one failed job of a batch rolls back alone.
class Savepoint {
 public:
  explicit Savepoint(Database& db);
  ~Savepoint();
  Savepoint(const Savepoint&) = delete;
  Savepoint& operator=(const Savepoint&) = delete;
  void Release();

 private:
  Database& db_;
  bool done_ = false;
};

}  // namespace pslam::server
