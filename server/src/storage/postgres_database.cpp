// The PostgreSQL engine of storage/database.hpp, over libpq. Each statement runs as one
// PQexecParams round trip with typed parameters (text for numbers, binary for blobs) and text
// results; '?' placeholders become $1, $2, ... outside quoted text. BEGIN waits for the
// transaction's first statement and goes with it in one round trip (libpq's pipeline mode).
#include <libpq-fe.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "storage/database.hpp"

namespace pslam::server {
namespace {

// Type OIDs of pg_type, fixed by PostgreSQL.
constexpr Oid kInt8Oid = 20, kFloat8Oid = 701, kTextOid = 25, kByteaOid = 17;

std::string Numbered(std::string_view sql) {
  std::string out;
  out.reserve(sql.size() + 16);
  char quote = 0;
  int next = 0;
  for (char c : sql) {
    if (quote) {
      if (c == quote) quote = 0;  // a doubled quote closes and reopens: same result
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '?') {
      out += '$' + std::to_string(++next);
      continue;
    }
    out += c;
  }
  return out;
}

std::string ErrorOf(PGconn* conn, const PGresult* result) {
  std::string message = result ? PQresultErrorMessage(result) : PQerrorMessage(conn);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

struct ResultDeleter {
  void operator()(PGresult* r) const { PQclear(r); }
};
using ResultPtr = std::unique_ptr<PGresult, ResultDeleter>;

bool Succeeded(const PGresult* r) {
  const ExecStatusType status = r ? PQresultStatus(r) : PGRES_FATAL_ERROR;
  return status == PGRES_TUPLES_OK || status == PGRES_COMMAND_OK;
}

// A query's result in pipeline mode; the NULL that ends it is read too.
ResultPtr NextResult(PGconn* conn) {
  ResultPtr result(PQgetResult(conn));
  while (PGresult* extra = PQgetResult(conn)) PQclear(extra);
  return result;
}

// BEGIN and a transaction's first statement in one round trip. Returns the statement's result, or
// BEGIN's if that failed (then the statement did not run).
ResultPtr ExecAfterBegin(PGconn* conn, const char* sql, int n, const Oid* types, const char* const* values,
                         const int* lengths, const int* formats) {
  if (PQenterPipelineMode(conn) != 1) return nullptr;
  const bool sent = PQsendQueryParams(conn, "BEGIN", 0, nullptr, nullptr, nullptr, nullptr, 0) == 1 &&
                    PQsendQueryParams(conn, sql, n, types, values, lengths, formats, 0) == 1 &&
                    PQpipelineSync(conn) == 1;
  ResultPtr result;
  if (sent) {
    ResultPtr begin = NextResult(conn);
    result = NextResult(conn);
    ResultPtr sync(PQgetResult(conn));  // PGRES_PIPELINE_SYNC
    if (!Succeeded(begin.get())) result = std::move(begin);
  }
  PQexitPipelineMode(conn);
  return result;
}

class PostgresStatement final : public StatementEngine {
 public:
  PostgresStatement(PGconn* conn, int& changes, bool& begin_pending, std::string_view sql)
      : conn_(conn), changes_(changes), begin_pending_(begin_pending), sql_(Numbered(sql)) {}

  void Bind(int index, std::int64_t value) override { Set(index, std::to_string(value), kInt8Oid, 0); }
  void Bind(int index, double value) override {
    if (std::isnan(value)) return Set(index, "NaN", kFloat8Oid, 0);
    if (std::isinf(value)) return Set(index, value > 0 ? "Infinity" : "-Infinity", kFloat8Oid, 0);
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);  // round-trips exactly
    Set(index, text, kFloat8Oid, 0);
  }
  void Bind(int index, std::string_view text) override { Set(index, std::string(text), kTextOid, 0); }
  void Bind(int index, std::span<const std::uint8_t> blob) override {
    Set(index, std::string(reinterpret_cast<const char*>(blob.data()), blob.size()), kByteaOid, 1);
  }
  void BindNull(int index) override {
    Grow(index);
    params_[index - 1] = Param{};
  }

  bool Step() override {
    if (!result_) Execute();
    return ++row_ < PQntuples(result_.get());
  }
  void Reset() override {
    result_.reset();
    row_ = -1;
    params_.clear();
  }

  bool IsNull(int column) const override { return PQgetisnull(result_.get(), row_, column) != 0; }
  std::int64_t Int64(int column) const override { return std::strtoll(Value(column), nullptr, 10); }
  double Double(int column) const override { return std::strtod(Value(column), nullptr); }  // also NaN, Infinity
  std::string Text(int column) const override {
    return std::string(Value(column), static_cast<std::size_t>(PQgetlength(result_.get(), row_, column)));
  }
  std::vector<std::uint8_t> Blob(int column) const override {
    std::size_t size = 0;
    unsigned char* raw = PQunescapeBytea(reinterpret_cast<const unsigned char*>(Value(column)), &size);
    if (!raw) throw StorageError("cannot decode a bytea value of '" + sql_.substr(0, 80) + "'");
    std::vector<std::uint8_t> out(raw, raw + size);
    PQfreemem(raw);
    return out;
  }

 private:
  struct Param {
    std::optional<std::string> value;
    Oid type = 0;  // 0: the server infers it (NULL)
    int format = 0;
  };

  void Grow(int index) {
    if (index < 1) throw StorageError("bind index " + std::to_string(index) + " in '" + sql_.substr(0, 80) + "'");
    if (params_.size() < static_cast<std::size_t>(index)) params_.resize(static_cast<std::size_t>(index));
  }
  void Set(int index, std::string value, Oid type, int format) {
    Grow(index);
    params_[index - 1] = Param{std::move(value), type, format};
  }
  const char* Value(int column) const {
    if (row_ < 0 || row_ >= PQntuples(result_.get()) || column < 0 || column >= PQnfields(result_.get())) {
      throw StorageError("no such row or column in '" + sql_.substr(0, 80) + "'");
    }
    return PQgetvalue(result_.get(), row_, column);
  }

  void Execute() {
    const int n = static_cast<int>(params_.size());
    std::vector<const char*> values(params_.size());
    std::vector<int> lengths(params_.size()), formats(params_.size());
    std::vector<Oid> types(params_.size());
    for (std::size_t i = 0; i < params_.size(); ++i) {
      values[i] = params_[i].value ? params_[i].value->data() : nullptr;
      lengths[i] = params_[i].value ? static_cast<int>(params_[i].value->size()) : 0;
      formats[i] = params_[i].format;
      types[i] = params_[i].type;
    }
    if (begin_pending_) {
      begin_pending_ = false;
      result_ = ExecAfterBegin(conn_, sql_.c_str(), n, types.data(), values.data(), lengths.data(), formats.data());
    } else {
      result_.reset(PQexecParams(conn_, sql_.c_str(), n, types.data(), values.data(), lengths.data(), formats.data(), 0));
    }
    if (!Succeeded(result_.get())) {
      const std::string message = ErrorOf(conn_, result_.get());
      result_.reset();
      throw StorageError("'" + sql_.substr(0, 80) + "': " + message);
    }
    changes_ = std::atoi(PQcmdTuples(result_.get()));
    row_ = -1;
  }

  PGconn* conn_;
  int& changes_;
  bool& begin_pending_;
  std::string sql_;
  std::vector<Param> params_;
  ResultPtr result_;
  int row_ = -1;
};

class PostgresDatabase final : public DatabaseEngine {
 public:
  explicit PostgresDatabase(PGconn* conn) : conn_(conn) {}
  ~PostgresDatabase() override { PQfinish(conn_); }
  PostgresDatabase(const PostgresDatabase&) = delete;
  PostgresDatabase& operator=(const PostgresDatabase&) = delete;

  StorageKind kind() const override { return StorageKind::kPostgres; }
  void Exec(std::string_view sql) override {
    if (sql == "BEGIN") {
      begin_pending_ = true;  // sent with the first statement
      return;
    }
    if (begin_pending_ && (sql == "COMMIT" || sql == "ROLLBACK")) {
      begin_pending_ = false;  // nothing ran: nothing to end
      return;
    }
    // Several statements in one PQexec run in one round trip.
    const std::string text = begin_pending_ ? "BEGIN; " + std::string(sql) : std::string(sql);
    begin_pending_ = false;
    ResultPtr result(PQexec(conn_, text.c_str()));
    if (!Succeeded(result.get())) {
      throw StorageError("exec '" + text.substr(0, 80) + "': " + ErrorOf(conn_, result.get()));
    }
  }
  std::unique_ptr<StatementEngine> Prepare(std::string_view sql) override {
    return std::make_unique<PostgresStatement>(conn_, changes_, begin_pending_, sql);
  }
  int Changes() const override { return changes_; }
  const char* BeginSql() const override { return "BEGIN"; }
  int SchemaVersion() override {
    CreateVersionTable();
    PostgresStatement s(conn_, changes_, begin_pending_, "SELECT COALESCE(MAX(version), 0) FROM schema_version");
    s.Step();
    return static_cast<int>(s.Int64(0));
  }
  void SetSchemaVersion(int version) override {
    CreateVersionTable();
    Exec("DELETE FROM schema_version");
    PostgresStatement s(conn_, changes_, begin_pending_, "INSERT INTO schema_version (version) VALUES (?)");
    s.Bind(1, static_cast<std::int64_t>(version));
    s.Step();
  }

 private:
  void CreateVersionTable() { Exec("CREATE TABLE IF NOT EXISTS schema_version (version BIGINT NOT NULL)"); }

  PGconn* conn_;
  int changes_ = 0;
  bool begin_pending_ = false;  // BEGIN was asked for and not sent yet
};

void IgnoreNotice(void*, const char*) {}  // "relation already exists, skipping" and the like

}  // namespace

Database Database::Connect(const std::string& url) {
  PGconn* conn = PQconnectdb(url.c_str());
  if (!conn || PQstatus(conn) != CONNECTION_OK) {
    std::string message = conn ? PQerrorMessage(conn) : "out of memory";
    while (!message.empty() && message.back() == '\n') message.pop_back();
    PQfinish(conn);
    throw StorageError("cannot connect to PostgreSQL: " + message);
  }
  PQsetNoticeProcessor(conn, IgnoreNotice, nullptr);
  return Database(std::make_unique<PostgresDatabase>(conn));
}

}  // namespace pslam::server
