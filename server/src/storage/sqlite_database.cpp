// The SQLite engine of storage/database.hpp.
#include <sqlite3.h>

#include <utility>

#include "storage/database.hpp"

namespace pslam::server {
namespace {

[[noreturn]] void Throw(sqlite3* db, int rc, std::string_view context) {
  std::string message(context);
  message += ": ";
  message += db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  throw StorageError(message);
}

class SqliteStatement final : public StatementEngine {
 public:
  SqliteStatement(sqlite3* db, std::string_view sql) : db_(db) {
    const int rc = sqlite3_prepare_v2(db, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) Throw(db, rc, "prepare '" + std::string(sql.substr(0, 80)) + "'");
  }
  ~SqliteStatement() override { sqlite3_finalize(stmt_); }
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  void Bind(int index, std::int64_t value) override { Check(sqlite3_bind_int64(stmt_, index, value)); }
  void Bind(int index, double value) override { Check(sqlite3_bind_double(stmt_, index, value)); }
  void Bind(int index, std::string_view text) override {
    Check(sqlite3_bind_text64(stmt_, index, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8));
  }
  void Bind(int index, std::span<const std::uint8_t> blob) override {
    // A zero-length blob must still be a blob, not NULL: sqlite binds a null pointer as NULL.
    static const std::uint8_t kEmpty = 0;
    Check(sqlite3_bind_blob64(stmt_, index, blob.empty() ? &kEmpty : blob.data(), blob.size(), SQLITE_TRANSIENT));
  }
  void BindNull(int index) override { Check(sqlite3_bind_null(stmt_, index)); }

  bool Step() override {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    Throw(db_, rc, "step '" + Sql() + "'");
  }
  void Reset() override {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }

  bool IsNull(int column) const override { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }
  std::int64_t Int64(int column) const override { return sqlite3_column_int64(stmt_, column); }
  double Double(int column) const override { return sqlite3_column_double(stmt_, column); }
  std::string Text(int column) const override {
    const auto* text = sqlite3_column_text(stmt_, column);
    return text ? std::string(reinterpret_cast<const char*>(text),
                              static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column)))
                : std::string();
  }
  std::vector<std::uint8_t> Blob(int column) const override {
    const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, column));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column));
    return data ? std::vector<std::uint8_t>(data, data + size) : std::vector<std::uint8_t>();
  }

 private:
  std::string Sql() const { return std::string(sqlite3_sql(stmt_)).substr(0, 80); }
  void Check(int rc) const {
    if (rc != SQLITE_OK) Throw(db_, rc, "bind in '" + Sql() + "'");
  }

  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

class SqliteDatabase final : public DatabaseEngine {
 public:
  explicit SqliteDatabase(sqlite3* db) : db_(db) {}
  ~SqliteDatabase() override { sqlite3_close_v2(db_); }
  SqliteDatabase(const SqliteDatabase&) = delete;
  SqliteDatabase& operator=(const SqliteDatabase&) = delete;

  StorageKind kind() const override { return StorageKind::kSqlite; }
  void Exec(std::string_view sql) override {
    const std::string text(sql);  // sqlite3_exec needs a terminated string
    char* error = nullptr;
    const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &error);
    if (rc != SQLITE_OK) {
      const std::string message = error ? error : sqlite3_errstr(rc);
      sqlite3_free(error);
      throw StorageError("exec '" + text.substr(0, 80) + "': " + message);
    }
  }
  std::unique_ptr<StatementEngine> Prepare(std::string_view sql) override {
    return std::make_unique<SqliteStatement>(db_, sql);
  }
  int Changes() const override { return sqlite3_changes(db_); }
  const char* BeginSql() const override { return "BEGIN IMMEDIATE"; }  // take the write lock now, not mid-way
  int SchemaVersion() override {
    SqliteStatement s(db_, "PRAGMA user_version");
    s.Step();
    return static_cast<int>(s.Int64(0));
  }
  void SetSchemaVersion(int version) override {
    Exec("PRAGMA user_version = " + std::to_string(version));  // an integer we own, not input
  }
  void Checkpoint() override { Exec("PRAGMA wal_checkpoint(TRUNCATE)"); }

 private:
  sqlite3* db_;
};

}  // namespace

Database Database::Open(const std::string& path, Mode mode, bool synchronous_full) {
  sqlite3* db = nullptr;
  const int flags = (mode == Mode::kReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) |
                    SQLITE_OPEN_NOMUTEX;  // each connection is used by one thread at a time
  const int rc = sqlite3_open_v2(path.c_str(), &db, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    sqlite3_close(db);
    throw StorageError("cannot open database " + path + ": " + message);
  }
  Database database(std::make_unique<SqliteDatabase>(db));
  // Readers wait for the writer's lock instead of failing with SQLITE_BUSY at once.
  sqlite3_busy_timeout(db, 5000);
  if (mode == Mode::kReadWrite) {
    database.Exec("PRAGMA journal_mode=WAL");
    database.Exec(synchronous_full ? "PRAGMA synchronous=FULL" : "PRAGMA synchronous=NORMAL");
  }
  database.Exec("PRAGMA foreign_keys=ON");
  return database;
}

}  // namespace pslam::server
