#include "storage/session_repository.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <variant>

#include "common/zlib_codec.hpp"

namespace pslam::server {
namespace {

static_assert(std::endian::native == std::endian::little, "blobs are stored little-endian; add byte swapping here");

using Value = std::variant<std::int64_t, double, std::string>;

// A WHERE clause made of fixed fragments, each with its bound values.
struct Where {
  std::string sql;
  std::vector<Value> values;
  void Add(const char* fragment, Value value) {
    sql += sql.empty() ? " WHERE " : " AND ";
    sql += fragment;
    values.push_back(std::move(value));
  }
  void AddMany(const char* fragment, std::vector<Value> more) {
    sql += sql.empty() ? " WHERE " : " AND ";
    sql += fragment;
    for (auto& v : more) values.push_back(std::move(v));
  }
  int BindTo(Statement& s, int first = 1) const {
    int index = first;
    for (const Value& v : values) std::visit([&](const auto& x) { s.Bind(index++, x); }, v);
    return index;
  }
};

// One page of the rows of 'table' that match 'where', in 'order', read by 'read'; returns how many
// rows match in all.
template <typename Row, typename Reader>
std::int64_t SelectPage(Database& db, const std::string& table, const char* columns, const Where& where,
                        const char* order, int limit, int offset, Reader read, std::vector<Row>& rows) {
  Statement count = db.Prepare("SELECT COUNT(*) FROM " + table + where.sql);
  where.BindTo(count);
  count.Step();
  const std::int64_t total = count.Int64(0);
  Statement s = db.Prepare(std::string("SELECT ") + columns + " FROM " + table + where.sql + " ORDER BY " + order +
                           " LIMIT ? OFFSET ?");
  const int next = where.BindTo(s);
  s.Bind(next, limit).Bind(next + 1, offset);
  while (s.Step()) rows.push_back(read(s));
  return total;
}

// LIKE with the user's text matched literally: % and _ in it are escaped.
std::string LikeContains(const std::string& text) {
  std::string out = "%";
  for (char c : text) {
    if (c == '%' || c == '_' || c == '\\') out += '\\';
    out += c;
  }
  return out + "%";
}

std::vector<std::uint8_t> RangesBlob(const std::vector<float>& ranges) {
  std::vector<std::uint8_t> out(ranges.size() * sizeof(float));
  if (!ranges.empty()) std::memcpy(out.data(), ranges.data(), out.size());
  return out;
}

std::vector<float> RangesFromBlob(const std::vector<std::uint8_t>& blob) {
  std::vector<float> out(blob.size() / sizeof(float));
  if (!out.empty()) std::memcpy(out.data(), blob.data(), out.size() * sizeof(float));
  return out;
}

constexpr std::size_t kCellBytes = 12;  // int32 x, int32 y, float32 occupancy
constexpr std::size_t kMaxHypothesisCells = 1 << 22;

std::vector<std::uint8_t> CellsBlob(const std::vector<PredictedCell>& cells) {
  std::vector<std::uint8_t> raw(cells.size() * kCellBytes);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::int32_t x = cells[i].x, y = cells[i].y;
    std::memcpy(&raw[i * kCellBytes], &x, 4);
    std::memcpy(&raw[i * kCellBytes + 4], &y, 4);
    std::memcpy(&raw[i * kCellBytes + 8], &cells[i].occupancy, 4);
  }
  return ZlibCompress(raw);
}

std::vector<PredictedCell> CellsFromBlob(const std::vector<std::uint8_t>& blob, std::int64_t count) {
  const auto n = static_cast<std::size_t>(std::clamp<std::int64_t>(count, 0, kMaxHypothesisCells));
  const auto raw = ZlibDecompress(blob, n * kCellBytes);
  std::vector<PredictedCell> cells;
  if (!raw) return cells;
  cells.resize(raw->size() / kCellBytes);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::int32_t x = 0, y = 0;
    std::memcpy(&x, &(*raw)[i * kCellBytes], 4);
    std::memcpy(&y, &(*raw)[i * kCellBytes + 4], 4);
    std::memcpy(&cells[i].occupancy, &(*raw)[i * kCellBytes + 8], 4);
    cells[i].x = x;
    cells[i].y = y;
  }
  return cells;
}

constexpr const char* kSessionColumns =
    "id, name, robot_id, source, replay_of, status, created_at, updated_at, closed_at, laser_json, settings_json, "
    "processed_seq, scans, stats_json, metrics_json, "
    "COALESCE((SELECT MAX(seq) FROM inputs WHERE inputs.session_id = sessions.id), 0), failure, rebuilds, rebuild_seq";

SessionRow ReadSession(const Statement& s) {
  SessionRow row;
  row.id = s.Text(0);
  row.name = s.Text(1);
  row.robot_id = s.Text(2);
  row.source = s.Text(3);
  if (!s.IsNull(4)) row.replay_of = s.Text(4);
  row.status = s.Text(5);
  row.created_at = s.Double(6);
  row.updated_at = s.Double(7);
  if (!s.IsNull(8)) row.closed_at = s.Double(8);
  row.laser_json = s.Text(9);
  row.settings_json = s.Text(10);
  row.processed_seq = s.Int64(11);
  row.scans = s.Int64(12);
  row.stats_json = s.Text(13);
  row.metrics_json = s.Text(14);
  row.last_seq = s.Int64(15);
  if (!s.IsNull(16)) row.failure = s.Text(16);
  row.rebuilds = s.Int64(17);
  row.rebuild_seq = s.Int64(18);
  return row;
}

constexpr const char* kHypothesisColumns =
    "id, t, target_cx, target_cy, reference_cx, reference_cy, theta, translation_x, translation_y, psi, area, cells, "
    "cell_count, status, hit_ratio, psi_observed, reference_site, reference_version";

HypothesisRecord ReadHypothesis(const Statement& s) {
  HypothesisRecord h;
  h.id = s.Int64(0);
  h.time = s.Double(1);
  h.target_cell = {s.Int(2), s.Int(3)};
  h.reference_cell = {s.Int(4), s.Int(5)};
  h.theta = s.Double(6);
  h.translation_x = s.Double(7);
  h.translation_y = s.Double(8);
  h.psi = s.Double(9);
  h.area = s.Double(10);
  h.cells = CellsFromBlob(s.Blob(11), s.Int64(12));
  h.status = s.Text(13);
  h.hit_ratio = s.Double(14);
  h.psi_observed = s.Double(15);
  if (!s.IsNull(16)) h.reference_map = SiteMapRef{s.Text(16), s.Int64(17)};
  return h;
}

}  // namespace

void SessionRepository::CreateSession(const SessionRow& row) {
  db_.Prepare(
         "INSERT INTO sessions (id, name, robot_id, source, replay_of, status, created_at, updated_at, laser_json, "
         "settings_json) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
      .BindAll(row.id, row.name, row.robot_id, row.source, row.replay_of, row.status, row.created_at, row.updated_at,
               row.laser_json, row.settings_json)
      .Run();
}

std::optional<SessionRow> SessionRepository::GetSession(const std::string& id) {
  Statement s = db_.Prepare(std::string("SELECT ") + kSessionColumns + " FROM sessions WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return ReadSession(s);
}

SessionPage SessionRepository::ListSessions(const SessionFilter& filter) {
  Where where;
  if (filter.status) where.Add("status = ?", *filter.status);
  if (filter.source) where.Add("source = ?", *filter.source);
  if (filter.robot_id) where.Add("robot_id = ?", *filter.robot_id);
  if (filter.name_contains) where.Add("name LIKE ? ESCAPE '\\'", LikeContains(*filter.name_contains));
  if (filter.created_after) where.Add("created_at >= ?", *filter.created_after);
  if (filter.created_before) where.Add("created_at < ?", *filter.created_before);
  SessionPage page;
  page.total = SelectPage(db_, "sessions", kSessionColumns, where, "created_at DESC, id", filter.limit, filter.offset,
                          ReadSession, page.sessions);
  return page;
}

std::vector<std::string> SessionRepository::SessionIdsWithStatus(const std::string& status) {
  Statement s = db_.Prepare("SELECT id FROM sessions WHERE status = ? ORDER BY created_at");
  s.Bind(1, status);
  std::vector<std::string> ids;
  while (s.Step()) ids.push_back(s.Text(0));
  return ids;
}

bool SessionRepository::DeleteSession(const std::string& id) {
  db_.Prepare("DELETE FROM events WHERE session_id = ?").BindAll(id).Run();
  db_.Prepare("DELETE FROM sessions WHERE id = ?").BindAll(id).Run();
  return db_.Changes() > 0;
}

void SessionRepository::SetStatus(const std::string& id, const std::string& status, double now) {
  db_.Prepare(
         "UPDATE sessions SET status = ?, updated_at = ?, "
         "closed_at = CASE WHEN ? = 'active' THEN NULL ELSE ? END WHERE id = ?")
      .BindAll(status, now, status, now, id)
      .Run();
}

void SessionRepository::SetFailed(const std::string& id, const std::string& reason, double now) {
  SetStatus(id, "failed", now);
  db_.Prepare("UPDATE sessions SET failure = ? WHERE id = ?").BindAll(reason, id).Run();
}

void SessionRepository::SetRebuilds(const std::string& id, std::int64_t rebuilds, std::int64_t rebuild_seq) {
  db_.Prepare("UPDATE sessions SET rebuilds = ?, rebuild_seq = ? WHERE id = ?").BindAll(rebuilds, rebuild_seq, id).Run();
}

void SessionRepository::SetMetrics(const std::string& id, const std::string& metrics_json) {
  db_.Prepare("UPDATE sessions SET metrics_json = ? WHERE id = ?").BindAll(metrics_json, id).Run();
}

namespace {

constexpr const char* kInputColumns = "session_id, seq, kind, t, x, y, theta, v, w, ranges, stamp";

// Binds an input's eleven values from parameter 'first' on.
void BindInput(Statement& s, int first, const std::string& session_id, const InputRecord& in) {
  const int o = first - 1;
  s.Bind(o + 1, session_id).Bind(o + 2, in.seq).Bind(o + 3, static_cast<int>(in.kind)).Bind(o + 4, in.t);
  s.Bind(o + 5, in.x).Bind(o + 6, in.y).Bind(o + 7, in.theta).Bind(o + 8, in.v).Bind(o + 9, in.w);
  if (in.kind == InputKind::kScan) {
    s.Bind(o + 10, std::span<const std::uint8_t>(RangesBlob(in.ranges)));
  } else {
    s.Bind(o + 10, nullptr);
  }
  if (in.stamp.empty()) {
    s.Bind(o + 11, nullptr);
  } else {
    s.Bind(o + 11, in.stamp);
  }
}

}  // namespace

void SessionRepository::InsertInput(const std::string& session_id, const InputRecord& in) {
  Statement s = db_.Prepare(std::string("INSERT INTO inputs (") + kInputColumns +
                            ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT DO NOTHING");
  BindInput(s, 1, session_id, in);
  s.Run();
}

bool SessionRepository::InsertInputFenced(const std::string& session_id, const InputRecord& in,
                                          const LeaseFence& fence) {
  // The insert reads the locked lease row: no lease, no row to insert.
  Statement s = db_.Prepare(
      std::string("WITH fence AS (SELECT 1 FROM session_leases WHERE session_id = ? AND node_id = ? AND epoch = ? "
                  "FOR SHARE), stored AS (INSERT INTO inputs (") +
      kInputColumns +
      ") SELECT ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ? FROM fence ON CONFLICT DO NOTHING RETURNING 1) "
      "SELECT COUNT(*) FROM fence");
  s.BindAll(session_id, fence.node_id, fence.epoch);
  BindInput(s, 4, session_id, in);
  s.Step();
  return s.Int64(0) > 0;
}

std::int64_t SessionRepository::LastInputSeq(const std::string& session_id) {
  Statement s = db_.Prepare("SELECT COALESCE(MAX(seq), 0) FROM inputs WHERE session_id = ?");
  s.Bind(1, session_id);
  s.Step();
  return s.Int64(0);
}

std::int64_t SessionRepository::CountScans(const std::string& session_id) {
  Statement s = db_.Prepare("SELECT COUNT(*) FROM inputs WHERE session_id = ? AND kind = 2");
  s.Bind(1, session_id);
  s.Step();
  return s.Int64(0);
}

std::vector<InputRecord> SessionRepository::LoadInputs(const std::string& session_id, std::int64_t after_seq,
                                                       int limit) {
  Statement s = db_.Prepare(
      "SELECT seq, kind, t, x, y, theta, v, w, ranges, stamp FROM inputs WHERE session_id = ? AND seq > ? "
      "ORDER BY seq LIMIT ?");
  s.BindAll(session_id, after_seq, limit);
  std::vector<InputRecord> out;
  while (s.Step()) {
    InputRecord in;
    in.seq = s.Int64(0);
    in.kind = s.Int(1) == static_cast<int>(InputKind::kOdometry) ? InputKind::kOdometry : InputKind::kScan;
    in.t = s.Double(2);
    in.x = s.Double(3);
    in.y = s.Double(4);
    in.theta = s.Double(5);
    in.v = s.Double(6);
    in.w = s.Double(7);
    if (!s.IsNull(8)) in.ranges = RangesFromBlob(s.Blob(8));
    if (!s.IsNull(9)) in.stamp = s.Text(9);
    out.push_back(std::move(in));
  }
  return out;
}

void SessionRepository::WriteCheckpoint(const Checkpoint& c, double now) {
  Statement snapshot = db_.Prepare(
      "INSERT INTO map_snapshots (session_id, created_at, processed_seq, scans, resolution, tiles_written) "
      "VALUES (?, ?, ?, ?, ?, ?) RETURNING id");
  snapshot.BindAll(c.session_id, now, c.processed_seq, c.scans, c.resolution, static_cast<std::int64_t>(c.tiles.size()));
  snapshot.Step();
  const std::int64_t snapshot_id = snapshot.Int64(0);
  snapshot.Run();
  {
    Statement s = db_.Prepare(
        "INSERT INTO map_tiles (session_id, tx, ty, size, revision, snapshot_id, data) VALUES (?, ?, ?, ?, ?, ?, ?) "
        "ON CONFLICT (session_id, tx, ty) DO UPDATE SET size = excluded.size, revision = excluded.revision, "
        "snapshot_id = excluded.snapshot_id, data = excluded.data");
    for (const TileRow& t : c.tiles) {
      s.BindAll(c.session_id, t.tx, t.ty, t.size, t.revision, snapshot_id);
      s.Bind(7, std::span<const std::uint8_t>(t.data));
      s.Run();
      s.Reset();
    }
  }
  if (c.replace_trajectory) db_.Prepare("DELETE FROM trajectory WHERE session_id = ?").BindAll(c.session_id).Run();
  {
    Statement s = db_.Prepare(
        "INSERT INTO trajectory (session_id, scan_index, seq, t, stamp, x, y, theta) "
        "VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (session_id, scan_index) DO UPDATE SET seq = excluded.seq, "
        "t = excluded.t, stamp = excluded.stamp, x = excluded.x, y = excluded.y, theta = excluded.theta");
    for (const TrajectoryRow& r : c.trajectory) {
      s.BindAll(c.session_id, r.scan_index, r.seq, r.t);
      if (r.stamp.empty()) {
        s.Bind(5, nullptr);
      } else {
        s.Bind(5, r.stamp);
      }
      s.Bind(6, r.x).Bind(7, r.y).Bind(8, r.theta);
      s.Run();
      s.Reset();
    }
  }
  for (const HypothesisRecord& h : c.hypotheses) UpsertHypothesis(c.session_id, h, c.resolution, now);
  db_.Prepare("UPDATE sessions SET processed_seq = ?, scans = ?, stats_json = ?, updated_at = ? WHERE id = ?")
      .BindAll(c.processed_seq, c.scans, c.stats_json, now, c.session_id)
      .Run();
}

void SessionRepository::UpsertHypothesis(const std::string& session_id, const HypothesisRecord& h, double resolution,
                                         double now) {
  double min_x = std::numeric_limits<double>::max(), min_y = min_x;
  double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
  for (const PredictedCell& c : h.cells) {
    min_x = std::min(min_x, c.x * resolution);
    min_y = std::min(min_y, c.y * resolution);
    max_x = std::max(max_x, (c.x + 1) * resolution);
    max_y = std::max(max_y, (c.y + 1) * resolution);
  }
  if (h.cells.empty()) {  // a hypothesis without cells sits at its target cell
    min_x = max_x = h.target_cell.x * resolution;
    min_y = max_y = h.target_cell.y * resolution;
  }
  Statement previous = db_.Prepare("SELECT status, hit_ratio, psi_observed FROM hypotheses WHERE session_id = ? AND id = ?");
  previous.BindAll(session_id, h.id);
  const bool existed = previous.Step();
  const bool status_changed = !existed || previous.Text(0) != h.status;
  db_.Prepare(
         "INSERT INTO hypotheses (session_id, id, t, target_cx, target_cy, reference_cx, reference_cy, theta, "
         "translation_x, translation_y, psi, area, cells, cell_count, min_x, min_y, max_x, max_y, status, hit_ratio, "
         "psi_observed, updated_at, reference_site, reference_version) "
         "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
         "ON CONFLICT (session_id, id) DO UPDATE SET t = excluded.t, target_cx = excluded.target_cx, "
         "target_cy = excluded.target_cy, reference_cx = excluded.reference_cx, reference_cy = excluded.reference_cy, "
         "theta = excluded.theta, translation_x = excluded.translation_x, translation_y = excluded.translation_y, "
         "psi = excluded.psi, area = excluded.area, cells = excluded.cells, cell_count = excluded.cell_count, "
         "min_x = excluded.min_x, min_y = excluded.min_y, max_x = excluded.max_x, max_y = excluded.max_y, "
         "status = excluded.status, hit_ratio = excluded.hit_ratio, psi_observed = excluded.psi_observed, "
         "updated_at = excluded.updated_at, reference_site = excluded.reference_site, "
         "reference_version = excluded.reference_version")
      .BindAll(session_id, h.id, h.time, h.target_cell.x, h.target_cell.y, h.reference_cell.x, h.reference_cell.y,
               h.theta, h.translation_x, h.translation_y, h.psi, h.area, std::span<const std::uint8_t>(CellsBlob(h.cells)),
               static_cast<std::int64_t>(h.cells.size()), min_x, min_y, max_x, max_y, h.status, h.hit_ratio,
               h.psi_observed, now,
               h.reference_map ? std::optional<std::string>(h.reference_map->site) : std::nullopt,
               h.reference_map ? std::optional<std::int64_t>(h.reference_map->version) : std::nullopt)
      .Run();
  if (status_changed) {
    db_.Prepare(
           "INSERT INTO hypothesis_status (session_id, hypothesis_id, t, status, hit_ratio, psi_observed) "
           "VALUES (?, ?, ?, ?, ?, ?)")
        .BindAll(session_id, h.id, h.time, h.status, h.hit_ratio, h.psi_observed)
        .Run();
  }
}

std::vector<TileRow> SessionRepository::LoadTiles(const std::string& session_id) {
  Statement s = db_.Prepare("SELECT tx, ty, size, revision, data FROM map_tiles WHERE session_id = ? ORDER BY ty, tx");
  s.Bind(1, session_id);
  std::vector<TileRow> out;
  while (s.Step()) out.push_back({s.Int(0), s.Int(1), s.Int(2), s.Int64(3), s.Blob(4)});
  return out;
}

std::optional<TileRow> SessionRepository::LoadTile(const std::string& session_id, int tx, int ty) {
  Statement s = db_.Prepare("SELECT tx, ty, size, revision, data FROM map_tiles WHERE session_id = ? AND tx = ? AND ty = ?");
  s.BindAll(session_id, tx, ty);
  if (!s.Step()) return std::nullopt;
  return TileRow{s.Int(0), s.Int(1), s.Int(2), s.Int64(3), s.Blob(4)};
}

std::vector<TrajectoryRow> SessionRepository::LoadTrajectory(const std::string& session_id, std::int64_t from_index,
                                                             int limit) {
  Statement s = db_.Prepare(
      "SELECT scan_index, seq, t, stamp, x, y, theta FROM trajectory WHERE session_id = ? AND scan_index >= ? "
      "ORDER BY scan_index LIMIT ?");
  s.BindAll(session_id, from_index, limit);
  std::vector<TrajectoryRow> out;
  while (s.Step()) {
    out.push_back({s.Int64(0), s.Int64(1), s.Double(2), s.IsNull(3) ? std::string() : s.Text(3), s.Double(4),
                   s.Double(5), s.Double(6)});
  }
  return out;
}

HypothesisPage SessionRepository::QueryHypotheses(const std::string& session_id, const HypothesisFilter& f) {
  Where where;
  where.Add("session_id = ?", session_id);
  if (f.status) where.Add("status = ?", *f.status);
  if (f.min_psi) where.Add("psi >= ?", *f.min_psi);
  if (f.t_from) where.Add("t >= ?", *f.t_from);
  if (f.t_to) where.Add("t <= ?", *f.t_to);
  if (f.bbox) {
    const auto& b = *f.bbox;
    where.AddMany("max_x >= ? AND min_x <= ? AND max_y >= ? AND min_y <= ?", {b[0], b[2], b[1], b[3]});
  }
  HypothesisPage page;
  page.total = SelectPage(db_, "hypotheses", kHypothesisColumns, where, "id", f.limit, f.offset, ReadHypothesis,
                          page.hypotheses);
  return page;
}

std::optional<HypothesisRecord> SessionRepository::GetHypothesis(const std::string& session_id, std::int64_t id) {
  Statement s = db_.Prepare(std::string("SELECT ") + kHypothesisColumns + " FROM hypotheses WHERE session_id = ? AND id = ?");
  s.BindAll(session_id, id);
  if (!s.Step()) return std::nullopt;
  return ReadHypothesis(s);
}

std::vector<HypothesisStatusRow> SessionRepository::HypothesisHistory(const std::string& session_id, std::int64_t id) {
  Statement s = db_.Prepare(
      "SELECT hypothesis_id, t, status, hit_ratio, psi_observed FROM hypothesis_status "
      "WHERE session_id = ? AND hypothesis_id = ? ORDER BY id");
  s.BindAll(session_id, id);
  std::vector<HypothesisStatusRow> out;
  while (s.Step()) out.push_back({s.Int64(0), s.Double(1), s.Text(2), s.Double(3), s.Double(4)});
  return out;
}

HypothesisCounts SessionRepository::CountHypotheses(const std::string& session_id) {
  // Every stored hypothesis was accepted (its Psi passed the threshold); pending ones still wait
  // for the robot to see enough of them to be judged.
  Statement s = db_.Prepare(
      "SELECT COUNT(*), "
      "COALESCE(SUM(CASE WHEN status = 'pending' THEN 1 ELSE 0 END), 0), "
      "COALESCE(SUM(CASE WHEN status = 'confirmed' THEN 1 ELSE 0 END), 0), "
      "COALESCE(SUM(CASE WHEN status = 'refuted' THEN 1 ELSE 0 END), 0), "
      "COALESCE(SUM(CASE WHEN status = 'expired' THEN 1 ELSE 0 END), 0), "
      "COALESCE(AVG(CASE WHEN status IN ('pending', 'confirmed') THEN hit_ratio END), 0) "
      "FROM hypotheses WHERE session_id = ?");
  s.Bind(1, session_id);
  s.Step();
  return {s.Int64(0), s.Int64(1), s.Int64(2), s.Int64(3), s.Int64(4), s.Double(5)};
}

void SessionRepository::AddEvent(const std::optional<std::string>& session_id, const std::string& kind,
                                 const std::string& detail_json, double now) {
  db_.Prepare("INSERT INTO events (session_id, t, kind, detail) VALUES (?, ?, ?, ?)")
      .BindAll(session_id, now, kind, detail_json)
      .Run();
}

namespace {

std::vector<EventRow> ReadEvents(Statement& s) {
  std::vector<EventRow> out;
  while (s.Step()) {
    EventRow e;
    e.id = s.Int64(0);
    if (!s.IsNull(1)) e.session_id = s.Text(1);
    e.t = s.Double(2);
    e.kind = s.Text(3);
    e.detail_json = s.Text(4);
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

std::vector<EventRow> SessionRepository::ListEvents(const std::optional<std::string>& session_id, int limit,
                                                    int offset) {
  Statement s = session_id ? db_.Prepare("SELECT id, session_id, t, kind, detail FROM events WHERE session_id = ? "
                                         "ORDER BY id DESC LIMIT ? OFFSET ?")
                           : db_.Prepare("SELECT id, session_id, t, kind, detail FROM events WHERE session_id IS NULL "
                                         "ORDER BY id DESC LIMIT ? OFFSET ?");
  int index = 1;
  if (session_id) s.Bind(index++, *session_id);
  s.Bind(index, limit);
  s.Bind(index + 1, offset);
  return ReadEvents(s);
}

std::vector<EventRow> SessionRepository::ListEventsOfKind(const std::string& session_id, const std::string& kind) {
  Statement s = db_.Prepare("SELECT id, session_id, t, kind, detail FROM events WHERE session_id = ? AND kind = ? "
                            "ORDER BY id");
  s.Bind(1, session_id);
  s.Bind(2, kind);
  return ReadEvents(s);
}

}  // namespace pslam::server
