#pragma once
// The SQL of sessions (sites: site_repository.hpp), written once for both engines (SQLite and
// PostgreSQL). Every value is a bound parameter; filters build their WHERE clause from fixed
// fragments and bind the user's values, so no input ever becomes SQL.
#include <optional>
#include <string>
#include <vector>

#include "model/input.hpp"
#include "storage/records.hpp"
#include "storage/database.hpp"

namespace pslam::server {

// A fleet node's lease on a session at one epoch (session_leases): writes fenced by it fail once
// another node has taken the session over.
struct LeaseFence {
  std::string node_id;
  std::int64_t epoch = 0;
};

class SessionRepository {
 public:
  explicit SessionRepository(Database& db) : db_(db) {}
  // The connection, for the other repositories of the same database (SiteRepository).
  Database& database() { return db_; }

  // Sessions.
  void CreateSession(const SessionRow& row);
  std::optional<SessionRow> GetSession(const std::string& id);
  SessionPage ListSessions(const SessionFilter& filter);
  std::vector<std::string> SessionIdsWithStatus(const std::string& status);
  // Returns false if there is no such session.
  bool DeleteSession(const std::string& id);
  void SetStatus(const std::string& id, const std::string& status, double now);
  // Status failed, with the reason shown to operators.
  void SetFailed(const std::string& id, const std::string& reason, double now);
  void SetRebuilds(const std::string& id, std::int64_t rebuilds, std::int64_t rebuild_seq = 0);
  void SetMetrics(const std::string& id, const std::string& metrics_json);

  // Raw inputs. InsertInput ignores a seq that is already stored (a resend): exactly once.
  void InsertInput(const std::string& session_id, const InputRecord& input);
  // The same, fenced by a fleet lease (PostgreSQL only) in the same statement, so an input costs
  // one round trip: stores nothing and returns false unless 'fence' still holds the session's
  // lease, whose row stays locked (FOR SHARE) until the transaction ends.
  bool InsertInputFenced(const std::string& session_id, const InputRecord& input, const LeaseFence& fence);
  std::int64_t LastInputSeq(const std::string& session_id);
  std::int64_t CountScans(const std::string& session_id);
  // Inputs with seq > 'after_seq', in order, at most 'limit'.
  std::vector<InputRecord> LoadInputs(const std::string& session_id, std::int64_t after_seq, int limit);

  // Engine checkpoints and what they wrote.
  void WriteCheckpoint(const Checkpoint& checkpoint, double now);
  std::vector<TileRow> LoadTiles(const std::string& session_id);
  std::optional<TileRow> LoadTile(const std::string& session_id, int tx, int ty);
  std::vector<TrajectoryRow> LoadTrajectory(const std::string& session_id, std::int64_t from_index, int limit);

  // Hypotheses.
  HypothesisPage QueryHypotheses(const std::string& session_id, const HypothesisFilter& filter);
  std::optional<HypothesisRecord> GetHypothesis(const std::string& session_id, std::int64_t id);
  std::vector<HypothesisStatusRow> HypothesisHistory(const std::string& session_id, std::int64_t id);
  HypothesisCounts CountHypotheses(const std::string& session_id);

  // Events.
  void AddEvent(const std::optional<std::string>& session_id, const std::string& kind, const std::string& detail_json,
                double now);
  std::vector<EventRow> ListEvents(const std::optional<std::string>& session_id, int limit, int offset);
  // Every event of one kind of a session, oldest first.
  std::vector<EventRow> ListEventsOfKind(const std::string& session_id, const std::string& kind);

 private:
  void UpsertHypothesis(const std::string& session_id, const HypothesisRecord& h, double resolution, double now);

  Database& db_;
};

}  // namespace pslam::server
