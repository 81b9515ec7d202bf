#include "service/live_codec.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/tile_codec.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "service/json_views.hpp"

namespace pslam::server {
namespace {

std::string Dump(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

nlohmann::json PoseJson(const Pose2D& p) { return {{"type", "pose"}, {"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

// To 'decimals' places; dividing by an exact power of ten gives the double that prints shortest.
double Round(double v, int decimals) {
  if (decimals > 300) return 0.0;
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

double SignificantDigits(double v, int digits) {
  if (!(std::abs(v) > 0) || !std::isfinite(v)) return 0.0;
  return Round(v, digits - 1 - static_cast<int>(std::floor(std::log10(std::abs(v)))));
}

// Particles in the snapshot: poses to 1 mm and 0.001 rad, weights to 4 significant digits, which
// is all a viewer draws.
nlohmann::json ParticlesJson(const std::vector<Pose2D>& poses, const std::vector<double>& weights) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double w = i < weights.size() ? weights[i] : 0.0;
    list.push_back({Round(poses[i].x, 3), Round(poses[i].y, 3), Round(poses[i].theta, 3), SignificantDigits(w, 4)});
  }
  return list;
}

template <typename T>
void Put(std::string& out, std::size_t offset, T value) {
  std::memcpy(out.data() + offset, &value, sizeof(T));
}

nlohmann::json ExplorationJson(const LiveFrame& f) {
  nlohmann::json frontiers = nlohmann::json::array();
  for (const auto& p : f.frontiers) frontiers.push_back({p[0], p[1]});
  return {{"type", "exploration"},
          {"frontiers", frontiers},
          {"target", f.target ? TargetToJson(*f.target) : nlohmann::json()}};
}

nlohmann::json HypothesisEvent(const char* event, const nlohmann::json& body) {
  return {{"type", "hypothesis"}, {"event", event}, {"hypothesis", body}};
}

nlohmann::json TrajectoryPoses(std::span<const TrajectoryRow> rows) {
  nlohmann::json poses = nlohmann::json::array();
  for (const TrajectoryRow& r : rows) poses.push_back({r.x, r.y, r.theta, r.t});
  return poses;
}

nlohmann::json SnapshotJson(const std::string& session_id, const std::string& status, double resolution,
                            std::size_t tile_count) {
  return {{"type", "snapshot"},
          {"session_id", session_id},
          {"status", status},
          {"resolution", resolution},
          {"tile_size", OccupancyGrid::kTileSize},
          {"tile_count", tile_count}};
}

}  // namespace

Bytes EncodeTileFrame(int tx, int ty, std::uint64_t revision, std::span<const std::uint8_t> zlib_cells) {
  std::string out(kTileFrameHeader + zlib_cells.size(), '\0');
  const std::int32_t x = tx, y = ty;
  const auto size = static_cast<std::uint16_t>(OccupancyGrid::kTileSize);
  std::memcpy(out.data(), "PSTL", 4);
  std::memcpy(out.data() + 4, &x, 4);
  std::memcpy(out.data() + 8, &y, 4);
  std::memcpy(out.data() + 12, &size, 2);
  out[14] = static_cast<char>(kTileEncodingPercent);
  std::memcpy(out.data() + 16, &revision, 8);
  if (!zlib_cells.empty()) std::memcpy(out.data() + kTileFrameHeader, zlib_cells.data(), zlib_cells.size());
  return MakeBytes(std::move(out));
}

Bytes EncodeScanFrame(std::int64_t seq, const LaserScan& scan, const Pose2D& robot) {
  const std::size_t beams = std::min<std::size_t>(scan.ranges.size(), 65535);
  std::string out(kScanFrameHeader + 2 * beams, '\0');
  const Pose2D sensor = robot * scan.sensor_offset;
  std::memcpy(out.data(), "PSSC", 4);
  Put(out, 4, static_cast<std::uint16_t>(beams));
  out[6] = static_cast<char>(kScanEncodingCentimetres);
  Put(out, 8, seq);
  Put(out, 16, static_cast<float>(sensor.x));
  Put(out, 20, static_cast<float>(sensor.y));
  Put(out, 24, static_cast<float>(sensor.theta));
  Put(out, 28, static_cast<float>(scan.angle_min));
  Put(out, 32, static_cast<float>(scan.angle_increment));
  Put(out, 36, static_cast<float>(scan.max_range));
  for (std::size_t i = 0; i < beams; ++i) {
    const std::uint16_t cm = scan.IsReturn(i) ? static_cast<std::uint16_t>(std::min(std::round(scan.ranges[i] * 100.0), 65534.0))
                                              : kScanNoReturn;
    Put(out, kScanFrameHeader + 2 * i, cm);
  }
  return MakeBytes(std::move(out));
}

Bytes EncodeParticleFrame(std::span<const Pose2D> poses, std::span<const double> weights) {
  std::string out(kParticleFrameHeader + 16 * poses.size(), '\0');
  std::memcpy(out.data(), "PSPT", 4);
  Put(out, 4, static_cast<std::uint32_t>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::size_t at = kParticleFrameHeader + 16 * i;
    Put(out, at, static_cast<float>(poses[i].x));
    Put(out, at + 4, static_cast<float>(poses[i].y));
    Put(out, at + 8, static_cast<float>(poses[i].theta));
    Put(out, at + 12, static_cast<float>(i < weights.size() ? weights[i] : 0.0));
  }
  return MakeBytes(std::move(out));
}

Bytes TrajectoryMessage(std::int64_t first_index, std::span<const TrajectoryRow> rows) {
  return MakeBytes(Dump({{"type", "trajectory"}, {"first_index", first_index}, {"poses", TrajectoryPoses(rows)}}));
}

Bytes SessionStatusMessage(const std::string& session_id, const std::string& status) {
  return MakeBytes(Dump({{"type", "session"}, {"session_id", session_id}, {"status", status}}));
}

LiveDelta LiveState::Apply(const LiveFrame& f) {
  LiveDelta d;
  resolution_ = f.resolution;
  for (const LiveTile& t : f.tiles) {
    Bytes frame = EncodeTileFrame(t.tx, t.ty, t.revision, *t.cells);
    tiles_[{t.tx, t.ty}] = frame;
    d.tiles.emplace_back(TileKey{t.tx, t.ty}, std::move(frame));
  }
  // Pose and particles go out when they changed: a tick that only brings due stats, or a plan,
  // does not resend them.
  if (f.pose) {
    nlohmann::json pose = PoseJson(*f.pose);
    if (pose != pose_) {
      pose_ = std::move(pose);
      d.pose = MakeBytes(Dump(pose_));
    }
  }
  if (f.scan && f.pose && f.scan_seq != scan_seq_) {
    scan_seq_ = f.scan_seq;
    d.scan = EncodeScanFrame(f.scan_seq, *f.scan, *f.pose);
  }
  if (!f.particles.empty()) {
    // Compared as encoded (cheap); the snapshot's JSON is only rebuilt when the cloud changed.
    Bytes frame = EncodeParticleFrame(f.particles, f.weights);
    if (!particle_frame_ || *frame != *particle_frame_) {
      particle_frame_ = frame;
      particles_ = ParticlesJson(f.particles, f.weights);
      d.particles = std::move(frame);
    }
  }
  stats_ = {{"type", "stats"}, {"stats", EngineStatsToJson(f.stats)}};
  if (f.send_stats) d.stats = MakeBytes(Dump(stats_));
  nlohmann::json exploration = ExplorationJson(f);
  if (exploration != exploration_) {
    exploration_ = std::move(exploration);
    d.exploration = MakeBytes(Dump(exploration_));
  }
  if (!f.trajectory.empty()) {
    // Increments are contiguous: a restarted engine starts again at 0 and replaces the history.
    if (f.trajectory_first_index < static_cast<std::int64_t>(trajectory_.size())) {
      trajectory_.resize(static_cast<std::size_t>(f.trajectory_first_index));
    }
    trajectory_.insert(trajectory_.end(), f.trajectory.begin(), f.trajectory.end());
    d.trajectory_first_index = f.trajectory_first_index;
    d.trajectory = std::make_shared<const std::vector<TrajectoryRow>>(f.trajectory);
  }
  for (const HypothesisRecord& h : f.hypotheses_changed) {
    const bool known = hypotheses_.count(h.id) > 0;
    nlohmann::json body = HypothesisToJson(h, /*with_cells=*/false);
    hypotheses_[h.id] = body;
    d.hypotheses.emplace_back(h.id, MakeBytes(Dump(HypothesisEvent(known ? "updated" : "added", body))));
  }
  for (std::int64_t id : f.hypotheses_removed) {
    hypotheses_.erase(id);
    d.hypotheses.emplace_back(id, MakeBytes(Dump(HypothesisEvent("removed", {{"id", id}}))));
  }
  return d;
}

std::vector<LiveMessage> LiveState::Snapshot() const {
  nlohmann::json s = SnapshotJson(session_id_, "active", resolution_, tiles_.size());
  s["pose"] = pose_.is_null() ? nlohmann::json() : nlohmann::json{{"x", pose_["x"]}, {"y", pose_["y"]}, {"theta", pose_["theta"]}};
  s["trajectory"] = {{"first_index", 0}, {"poses", TrajectoryPoses(trajectory_)}};
  s["particles"] = particles_.is_null() ? nlohmann::json::array() : particles_;
  nlohmann::json hypotheses = nlohmann::json::array();
  for (const auto& [id, body] : hypotheses_) hypotheses.push_back(body);
  s["hypotheses"] = std::move(hypotheses);
  s["frontiers"] = exploration_.is_null() ? nlohmann::json::array() : exploration_["frontiers"];
  s["target"] = exploration_.is_null() ? nlohmann::json() : exploration_["target"];
  s["stats"] = stats_.is_null() ? nlohmann::json::object() : stats_["stats"];
  std::vector<LiveMessage> out;
  out.reserve(tiles_.size() + 1);
  out.push_back({MakeBytes(Dump(s)), false});
  for (const auto& [key, frame] : tiles_) out.push_back({frame, true});
  return out;
}

namespace {

// A message of 'type' with the fields the snapshot reads from it ('numbers' must be numbers).
nlohmann::json ParseMessage(const Bytes& bytes, const char* type, std::initializer_list<const char*> fields,
                            std::initializer_list<const char*> numbers = {}) {
  nlohmann::json j = nlohmann::json::parse(*bytes);
  if (!j.is_object() || j.value("type", "") != type) throw std::invalid_argument(std::string("not a ") + type + " message");
  for (const char* f : fields) {
    if (!j.contains(f)) throw std::invalid_argument(std::string(type) + " message without " + f);
  }
  for (const char* f : numbers) {
    if (!j.contains(f) || !j[f].is_number()) throw std::invalid_argument(std::string(type) + " message without a number " + f);
  }
  return j;
}

// The particle frame's poses and weights (the decoder checked its length).
nlohmann::json ParticlesOfFrame(const std::string& frame) {
  std::uint32_t n = 0;
  std::memcpy(&n, frame.data() + 4, 4);
  std::vector<Pose2D> poses(n);
  std::vector<double> weights(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    float v[4];
    std::memcpy(v, frame.data() + kParticleFrameHeader + 16 * std::size_t{i}, sizeof v);
    poses[i] = Pose2D(v[0], v[1], v[2]);
    weights[i] = v[3];
  }
  return ParticlesJson(poses, weights);
}

Bytes ParticleFrameOfJson(const nlohmann::json& particles) {
  std::vector<Pose2D> poses;
  std::vector<double> weights;
  for (const auto& p : particles) {
    poses.emplace_back(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
    weights.push_back(p.at(3).get<double>());
  }
  return EncodeParticleFrame(poses, weights);
}

TileKey KeyOfTileFrame(const std::string& frame) {
  std::int32_t x = 0, y = 0;
  std::memcpy(&x, frame.data() + 4, 4);
  std::memcpy(&y, frame.data() + 8, 4);
  return {x, y};
}

bool SamePoses(const std::vector<TrajectoryRow>& a, const std::vector<TrajectoryRow>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const TrajectoryRow& p, const TrajectoryRow& q) {
    return p.x == q.x && p.y == q.y && p.theta == q.theta && p.t == q.t;
  });
}

}  // namespace

void LiveState::Absorb(const LiveDelta& d) {
  // Everything that can throw first, so a bad message changes nothing.
  nlohmann::json pose = d.pose ? ParseMessage(d.pose, "pose", {}, {"x", "y", "theta"}) : pose_;
  nlohmann::json stats = d.stats ? ParseMessage(d.stats, "stats", {"stats"}) : stats_;
  nlohmann::json exploration = d.exploration ? ParseMessage(d.exploration, "exploration", {"frontiers", "target"}) : exploration_;
  std::vector<std::pair<std::int64_t, nlohmann::json>> events;
  for (const auto& [id, message] : d.hypotheses) {
    events.emplace_back(id, ParseMessage(message, "hypothesis", {"event"}));
    if (events.back().second["event"] != "removed" && !events.back().second.contains("hypothesis")) {
      throw std::invalid_argument("hypothesis event without a body");
    }
  }
  for (const auto& [key, frame] : d.tiles) tiles_[key] = frame;
  pose_ = std::move(pose);
  stats_ = std::move(stats);
  exploration_ = std::move(exploration);
  if (d.particles) {
    particle_frame_ = d.particles;
    particles_ = ParticlesOfFrame(*d.particles);
  }
  if (d.trajectory) {
    if (d.trajectory_first_index < static_cast<std::int64_t>(trajectory_.size())) {
      trajectory_.resize(static_cast<std::size_t>(std::max<std::int64_t>(0, d.trajectory_first_index)));
    }
    trajectory_.insert(trajectory_.end(), d.trajectory->begin(), d.trajectory->end());
  }
  for (auto& [id, event] : events) {
    if (event["event"] == "removed") {
      hypotheses_.erase(id);
    } else {
      hypotheses_[id] = std::move(event["hypothesis"]);
    }
  }
}

LiveDelta LiveState::Replace(const std::string& snapshot, const std::vector<Bytes>& tiles) {
  const nlohmann::json s = nlohmann::json::parse(snapshot);
  if (!s.is_object() || s.value("type", "") != "snapshot") throw std::invalid_argument("not a snapshot message");
  LiveState next(session_id_, s.at("resolution").get<double>());
  for (const Bytes& frame : tiles) next.tiles_[KeyOfTileFrame(*frame)] = frame;
  const nlohmann::json& pose = s.at("pose");
  if (!pose.is_null()) next.pose_ = PoseJson(Pose2D(pose.at("x").get<double>(), pose.at("y").get<double>(), pose.at("theta").get<double>()));
  for (const auto& p : s.at("trajectory").at("poses")) {
    TrajectoryRow row;
    row.scan_index = static_cast<std::int64_t>(next.trajectory_.size());
    row.x = p.at(0).get<double>();
    row.y = p.at(1).get<double>();
    row.theta = p.at(2).get<double>();
    row.t = p.at(3).get<double>();
    next.trajectory_.push_back(row);
  }
  if (!s.at("particles").empty()) {
    next.particles_ = s["particles"];
    next.particle_frame_ = ParticleFrameOfJson(next.particles_);
  }
  for (const auto& body : s.at("hypotheses")) next.hypotheses_[body.at("id").get<std::int64_t>()] = body;
  next.exploration_ = {{"type", "exploration"}, {"frontiers", s.at("frontiers")}, {"target", s.at("target")}};
  next.stats_ = {{"type", "stats"}, {"stats", s.at("stats")}};

  LiveDelta d;
  for (const auto& [key, frame] : next.tiles_) {
    const auto old = tiles_.find(key);
    if (old == tiles_.end() || *old->second != *frame) d.tiles.emplace_back(key, frame);
  }
  if (!next.pose_.is_null() && next.pose_ != pose_) d.pose = MakeBytes(Dump(next.pose_));
  if (next.particle_frame_ && (!particle_frame_ || *next.particle_frame_ != *particle_frame_)) d.particles = next.particle_frame_;
  d.stats = MakeBytes(Dump(next.stats_));
  if (next.exploration_ != exploration_) d.exploration = MakeBytes(Dump(next.exploration_));
  if (!next.trajectory_.empty() && !SamePoses(next.trajectory_, trajectory_)) {
    d.trajectory_first_index = 0;  // the whole trajectory replaces the viewer's
    d.trajectory = std::make_shared<const std::vector<TrajectoryRow>>(next.trajectory_);
  }
  for (const auto& [id, body] : next.hypotheses_) {
    const auto old = hypotheses_.find(id);
    if (old == hypotheses_.end() || old->second != body) {
      d.hypotheses.emplace_back(id, MakeBytes(Dump(HypothesisEvent(old == hypotheses_.end() ? "added" : "updated", body))));
    }
  }
  for (const auto& [id, body] : hypotheses_) {
    if (!next.hypotheses_.count(id)) d.hypotheses.emplace_back(id, MakeBytes(Dump(HypothesisEvent("removed", {{"id", id}}))));
  }
  *this = std::move(next);
  return d;
}

std::vector<LiveMessage> StoredSnapshot(const std::string& session_id, const std::string& status, double resolution,
                                        const std::vector<TileRow>& tiles, const std::vector<TrajectoryRow>& trajectory,
                                        const std::vector<HypothesisRecord>& hypotheses, const nlohmann::json& stats) {
  std::vector<LiveMessage> frames;
  for (const TileRow& t : tiles) {
    const auto live = StoredToLiveTile(t.data);
    if (live) frames.push_back({EncodeTileFrame(t.tx, t.ty, static_cast<std::uint64_t>(t.revision), *live), true});
  }
  nlohmann::json s = SnapshotJson(session_id, status, resolution, frames.size());
  s["pose"] = trajectory.empty() ? nlohmann::json()
                                 : nlohmann::json{{"x", trajectory.back().x}, {"y", trajectory.back().y},
                                                  {"theta", trajectory.back().theta}};
  s["trajectory"] = {{"first_index", 0}, {"poses", TrajectoryPoses(trajectory)}};
  s["particles"] = nlohmann::json::array();
  nlohmann::json list = nlohmann::json::array();
  for (const HypothesisRecord& h : hypotheses) list.push_back(HypothesisToJson(h, false));
  s["hypotheses"] = std::move(list);
  s["frontiers"] = nlohmann::json::array();
  s["target"] = nullptr;
  s["stats"] = stats;
  std::vector<LiveMessage> out;
  out.reserve(frames.size() + 1);
  out.push_back({MakeBytes(Dump(s)), false});
  for (auto& f : frames) out.push_back(std::move(f));
  return out;
}

}  // namespace pslam::server
