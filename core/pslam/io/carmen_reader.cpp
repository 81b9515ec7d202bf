#include "pslam/io/carmen_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <span>
#include <string_view>
#include <utility>

#include "pslam/io/bzip2_line_source.hpp"
#include "pslam/io/line_source.hpp"
#include "pslam/io/odometry_reversal.hpp"

#ifdef PSLAM_HAVE_ZLIB
#include <zlib.h>
#endif

namespace pslam {
namespace {

constexpr std::size_t kMaxReportedErrors = 20;
constexpr std::size_t kMaxUnknownTypes = 16;
constexpr double kCarmenMaxRange = 80.0;  // CARMEN's guess for old-format lasers (readlog.c)
constexpr double kDeg = std::numbers::pi / 180.0;
// A laser pose further than this from the robot pose in the same line is not a mount offset (some
// logs are said to store corrected poses in the first triple), so it is ignored.
constexpr double kMaxPlausibleMountOffset = 2.0;
// No robot's odometry reads 10,000 km (or radians): such a pose is corrupt, not a place to map.
constexpr double kMaxPlausibleCoordinate = 1e7;

using Tokens = std::span<const std::string_view>;

// ---------------------------------------------------------------------------------------------
// Line sources: plain streams, bzip2 (bzip2_line_source.hpp), and gzip through zlib when the build
// provides it.

class StreamSource : public LineSource {
 public:
  StreamSource(std::istream& in, std::unique_ptr<std::istream> owned = nullptr)
      : owned_(std::move(owned)), in_(in) {
    // Size the remaining input for progress(); non-seekable streams (pipes) stay "unknown".
    const auto start = in_.tellg();
    if (start != std::streampos(-1) && in_.seekg(0, std::ios::end)) {
      const auto end = in_.tellg();
      if (end != std::streampos(-1)) total_ = static_cast<double>(end - start);
    }
    in_.clear();
    if (start != std::streampos(-1)) in_.seekg(start);
  }
  bool ReadLine(std::string& line) override {
    line.clear();
    std::streambuf& in = *in_.rdbuf();
    bool any = false, too_long = false;
    for (int c = in.sbumpc(); c != std::char_traits<char>::eof(); c = in.sbumpc()) {
      any = true;
      consumed_ += 1.0;
      if (c == '\n') break;
      if (line.size() < kMaxLineBytes) {
        line.push_back(static_cast<char>(c));
      } else {
        too_long = true;
      }
    }
    if (!any) {
      done_ = true;
      return false;
    }
    if (too_long) throw LineTooLong();
    return true;
  }
  double Progress() const override {
    if (total_ <= 0.0) return 0.0;
    return done_ ? 1.0 : std::min(1.0, consumed_ / total_);
  }

 private:
  std::unique_ptr<std::istream> owned_;
  std::istream& in_;
  double total_ = 0.0, consumed_ = 0.0;
  bool done_ = false;
};

#ifdef PSLAM_HAVE_ZLIB
class GzSource : public LineSource {
 public:
  GzSource(const std::string& path, double compressed_size) : total_(compressed_size) {
    file_ = gzopen(path.c_str(), "rb");
    if (!file_) throw std::runtime_error("cannot open CARMEN log '" + path + "' with zlib");
    gzbuffer(file_, 1 << 17);
  }
  ~GzSource() override { gzclose(file_); }
  bool ReadLine(std::string& line) override {
    line.clear();
    char buf[1 << 14];
    bool too_long = false;
    while (gzgets(file_, buf, sizeof buf)) {  // a long line arrives in several pieces
      const std::size_t n = std::strlen(buf);
      const bool ends = n > 0 && buf[n - 1] == '\n';
      if (line.size() + n > kMaxLineBytes + (ends ? 1 : 0)) {
        too_long = true;
        line.clear();
      } else {
        line.append(buf, n);
      }
      if (ends) {
        if (too_long) throw LineTooLong();
        line.pop_back();
        return true;
      }
    }
    done_ = true;
    if (too_long) throw LineTooLong();
    // A truncated archive ends the input; its cut-off last line is then reported as corrupt.
    return !line.empty();
  }
  double Progress() const override {
    if (done_) return 1.0;
    return total_ > 0.0 ? std::min(1.0, static_cast<double>(gzoffset(file_)) / total_) : 0.0;
  }

 private:
  gzFile file_ = nullptr;
  double total_;
  bool done_ = false;
};
#endif

std::unique_ptr<LineSource> OpenPath(const std::string& path) {
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*file) throw std::runtime_error("cannot open CARMEN log '" + path + "': " + std::strerror(errno));
  char magic[3] = {0, 0, 0};
  file->read(magic, 3);
  const auto got = file->gcount();
  const bool gzip = got >= 2 && magic[0] == '\x1f' && magic[1] == '\x8b';
  const bool bzip2 = got == 3 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h';
  file->clear();
  file->seekg(0);
  if (bzip2) return std::make_unique<Bzip2LineSource>(path);
  if (gzip) {
#ifdef PSLAM_HAVE_ZLIB
    file->seekg(0, std::ios::end);
    const double size = static_cast<double>(file->tellg());
    return std::make_unique<GzSource>(path, size);
#else
    throw std::runtime_error("CARMEN log '" + path +
                             "' is gzip-compressed and this build has no zlib support: gunzip it first");
#endif
  }
  std::istream& in = *file;
  return std::make_unique<StreamSource>(in, std::move(file));
}

// ---------------------------------------------------------------------------------------------
// Tokens and numbers.

void Tokenize(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  constexpr std::string_view kSpace = " \t\r\v\f";
  std::size_t i = line.find_first_not_of(kSpace);
  while (i != std::string_view::npos) {
    const std::size_t end = std::min(line.find_first_of(kSpace, i), line.size());
    out.push_back(line.substr(i, end - i));
    i = line.find_first_not_of(kSpace, end);
  }
}

// from_chars is locale-independent and accepts nan/inf like CARMEN's strtod; it rejects a leading
// '+', which printf-style writers may emit, so that is skipped first.
bool ParseDouble(std::string_view s, double& v) {
  if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// A corrupt line: the message says what is wrong; the reader prefixes FILE:LINE.
struct LineError {
  std::string what;
};

// Typed access to one line's tokens, with errors that name the record type and the field.
class Fields {
 public:
  explicit Fields(Tokens tokens) : tok_(tokens) {}
  std::size_t size() const { return tok_.size(); }
  std::string_view operator[](std::size_t i) const { return tok_[i]; }

  double Number(std::size_t i, const char* field) const {
    double v;
    if (!ParseDouble(tok_[i], v)) Fail(std::string(field) + " is not a number: '" + std::string(tok_[i]) + "'");
    return v;
  }
  double Finite(std::size_t i, const char* field) const {
    const double v = Number(i, field);
    if (!std::isfinite(v)) Fail(std::string(field) + " is not finite: '" + std::string(tok_[i]) + "'");
    return v;
  }
  // Beam/remission counts are integers, read before the arrays they size.
  std::size_t Count(std::size_t i, const char* field) const {
    if (i >= tok_.size()) Fail(std::string("truncated line: missing ") + field);
    long long v = 0;
    const std::string_view s = tok_[i];
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size())
      Fail(std::string(field) + " is not an integer: '" + std::string(s) + "'");
    if (v < 0) Fail("negative " + std::string(field) + ": " + std::string(s));
    return static_cast<std::size_t>(v);
  }
  void ExpectSize(std::size_t expected, std::string_view layout) const {
    if (tok_.size() == expected) return;
    Fail("needs " + std::to_string(expected) + " tokens (" + std::string(layout) + "), got " +
         std::to_string(tok_.size()) + (tok_.size() < expected ? " (truncated line?)" : ""));
  }
  Pose2D PoseAt(std::size_t i, const char* which) const {
    const Pose2D pose{Finite(i, which), Finite(i + 1, which), Finite(i + 2, which)};
    if (std::abs(pose.x) > kMaxPlausibleCoordinate || std::abs(pose.y) > kMaxPlausibleCoordinate ||
        std::abs(pose.theta) > kMaxPlausibleCoordinate) {
      Fail(std::string(which) + " is implausibly far from the origin: '" + std::string(tok_[i]) + " " +
           std::string(tok_[i + 1]) + " " + std::string(tok_[i + 2]) + "'");
    }
    return pose;
  }
  [[noreturn]] void Fail(const std::string& what) const { throw LineError{std::string(tok_[0]) + ": " + what}; }

 private:
  Tokens tok_;
};

// Every record ends with ipc_timestamp hostname logger_timestamp.
void ReadTrailer(const Fields& f, double& timestamp, std::string* text) {
  const std::size_t n = f.size();
  timestamp = f.Finite(n - 3, "ipc_timestamp");
  if (text) *text = std::string(f[n - 3]);
  f.Number(n - 1, "logger_timestamp");
}

// "ROBOTLASER2" -> 2 for prefix "ROBOTLASER"; nullopt if the name is not prefix + digits.
std::optional<int> NumberedName(std::string_view name, std::string_view prefix) {
  if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) return std::nullopt;
  int k = 0;
  const std::string_view digits = name.substr(prefix.size());
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), k);
  if (ec != std::errc() || ptr != digits.data() + digits.size() || k < 0) return std::nullopt;
  return k;
}

// ---------------------------------------------------------------------------------------------
// Laser geometry.

enum class Mount { kFront, kRear, kOther };

Mount MountForLaserNumber(int k) { return k == 1 ? Mount::kFront : k == 2 ? Mount::kRear : Mount::kOther; }

struct LogParams {
  std::optional<double> front_offset, rear_offset;            // robot_{front,rear}laser_offset, m
  std::optional<double> front_max, rear_max;                  // robot_{front,rear}_laser_max, m
  std::optional<double> front_resolution, rear_resolution;    // laser_{front,rear}_laser_resolution, rad
};

// Beam spacing of old FLASER/RLASER lines, which do not state it. CARMEN's readlog.c guesses it
// from the count (protocol §7.2): 180/181 -> 1 deg, 360/361 -> 0.5 deg, 400/401 -> 0.25 deg, else a
// 180 deg fan. For the Intel log's 180 beams this means 1 deg spacing from -90 deg, i.e. the beams
// cover -90 ... +89 deg (CARMEN drops the last beam), NOT pi/179 spacing over -90 ... +90 deg (as
// some tools do), and not GMapping's symmetric +-1 ... +-90 deg (half a degree off from ours). A
// PARAM laser_*_laser_resolution (degrees) overrides the guess.
double OldFormatResolution(std::size_t n, std::optional<double> param_resolution) {
  if (param_resolution) return *param_resolution;
  switch (n) {
    case 180: case 181: return 1.0 * kDeg;
    case 360: case 361: return 0.5 * kDeg;
    case 400: case 401: return 0.25 * kDeg;
    default: return n > 1 ? std::numbers::pi / static_cast<double>(n - 1) : 0.0;
  }
}

// CARMEN starts every old-format scan at -90 deg. That is right for a 180 deg SICK fan (with or
// without its last beam) but not for narrower/wider fans: CARMEN's -90 deg for the 100 deg 0.25 deg
// mode is a known quirk (the physical scan is -50 ... +50 deg), so those fans are centred instead.
double OldFormatStartAngle(std::size_t n, double resolution) {
  if (n < 2) return 0.0;
  const double span = static_cast<double>(n - 1) * resolution;
  if (std::abs(span - std::numbers::pi) <= 1.5 * resolution) return -std::numbers::pi / 2.0;
  return -span / 2.0;
}

// Only lasers 1 (front) and 2 (rear) have offset parameters.
std::optional<double> OffsetParam(Mount mount, const LogParams& params) {
  if (mount == Mount::kFront) return params.front_offset;
  if (mount == Mount::kRear) return params.rear_offset;
  return std::nullopt;
}

// Mount of the laser on the robot: heading from the mount (rear lasers face backwards), position
// from PARAM when given, else from laser pose vs robot pose in the line (protocol §8).
Pose2D MountOffset(Mount mount, std::optional<double> param_x, const Pose2D* laser_pose, const Pose2D* robot_pose) {
  const double theta = mount == Mount::kRear ? std::numbers::pi : 0.0;
  if (param_x) return {*param_x, 0.0, theta};
  if (laser_pose && robot_pose) {
    const Pose2D d = Between(*robot_pose, *laser_pose);
    if (std::hypot(d.x, d.y) <= kMaxPlausibleMountOffset) return {d.x, d.y, theta};
  }
  return {0.0, 0.0, theta};
}

// ROBOTLASER/RAWLASER field, else PARAM, else the caller's default, else CARMEN's 80 m. The Intel
// log's 81.83 m "no echo" readings are thus beyond max range and never count as returns.
double MaxRange(std::optional<double> from_record, Mount mount, const LogParams& params, double default_max) {
  if (from_record && *from_record > 0.0) return *from_record;
  const std::optional<double> param = mount == Mount::kRear && params.rear_max ? params.rear_max : params.front_max;
  if (param) return *param;
  return default_max > 0.0 ? default_max : kCarmenMaxRange;
}

void ReadRanges(const Fields& f, std::size_t first, std::size_t n, LaserScan& scan) {
  scan.ranges.resize(n);
  // NaN or negative ranges are kept as they are: LaserScan::IsReturn treats them as no return.
  for (std::size_t i = 0; i < n; ++i) scan.ranges[i] = static_cast<float>(f.Number(first + i, "range"));
}

// Shared head of ROBOTLASERk and RAWLASERk: laser_type start_angle fov resolution max_range accuracy
// remission_mode n r1..rn m v1..vm. Returns the index of the first token after the remissions.
std::size_t ReadNewLaserHead(const Fields& f, std::size_t fixed_tokens, LaserScan& s, double& max_range) {
  if (f.size() < 9) f.Fail("truncated line: " + std::to_string(f.size()) + " tokens");
  f.Number(1, "laser_type");
  const double start = f.Finite(2, "start_angle"), fov = f.Finite(3, "fov");
  const double resolution = f.Finite(4, "angular_resolution");
  max_range = f.Finite(5, "maximum_range");
  f.Number(6, "accuracy");
  f.Number(7, "remission_mode");
  const std::size_t n = f.Count(8, "beam count");
  if (f.size() < n + 10) f.Fail("n=" + std::to_string(n) + " but only " + std::to_string(f.size()) + " tokens (truncated line?)");
  const std::size_t m = f.Count(9 + n, "remission count");
  f.ExpectSize(fixed_tokens + n + m, std::to_string(fixed_tokens) + "+n+m, n=" + std::to_string(n) + " m=" + std::to_string(m));
  ReadRanges(f, 9, n, s);
  for (std::size_t i = 0; i < m; ++i) f.Number(10 + n + i, "remission");
  s.angle_min = start;
  // fov spans first to last beam (protocol §7.1); it only stands in for a missing resolution.
  s.angle_increment = resolution != 0.0 || n < 2 ? resolution : fov / static_cast<double>(n - 1);
  return 10 + n + m;
}

struct ParsedScan {
  LaserScan scan;
  bool has_odometry = false;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

struct CarmenReader::Impl {
  struct Entry {
    double t;
    std::uint64_t seq;  // file order, to keep ties stable
    LogRecord record;
    bool has_odometry;
  };
  // std::push_heap builds a max-heap; "later" puts the earliest entry at the front.
  static bool Later(const Entry& a, const Entry& b) { return a.t != b.t ? a.t > b.t : a.seq > b.seq; }

  std::unique_ptr<LineSource> source;
  std::string name;
  CarmenReaderOptions options;
  CarmenReadStats stats;
  OdometryReversalRepair odometry_repair;
  LogParams params;
  std::vector<Entry> heap;
  std::uint64_t seq = 0;
  std::size_t line_number = 0;
  double newest = -std::numeric_limits<double>::infinity();
  double last_released = -std::numeric_limits<double>::infinity();
  bool eof = false;
  bool last_has_odometry = false;
  std::string line;
  std::vector<std::string_view> tokens;

  std::optional<LogRecord> Next();
  bool ReadRecord();
  bool HandleLine(Tokens tok);
  void Push(LogRecord record, double t, bool has_odometry);
  void Repair(Entry& e);
  void Note(const std::string& what);
  void Corrupt(const std::string& what);

  OdometryReading ParseOdom(const Fields& f) const;
  ParsedScan ParseOldLaser(const Fields& f, Mount mount) const;
  ParsedScan ParseRobotLaser(const Fields& f, Mount mount) const;
  ParsedScan ParseRawLaser(const Fields& f, Mount mount) const;
  void ParseParam(const Fields& f);
};

std::optional<LogRecord> CarmenReader::Impl::Next() {
  const double window = std::max(0.0, options.reorder_window_s);
  for (;;) {
    if (!heap.empty() && (eof || newest - heap.front().t >= window)) {
      std::pop_heap(heap.begin(), heap.end(), Later);
      Entry e = std::move(heap.back());
      heap.pop_back();
      last_released = e.t;
      last_has_odometry = e.has_odometry;
      if (options.repair_reversed_odometry) Repair(e);
      return std::move(e.record);
    }
    if (eof) return std::nullopt;
    if (!ReadRecord()) eof = true;
  }
}

// Reads lines until one record has been buffered; false at the end of the input.
bool CarmenReader::Impl::ReadRecord() {
  for (;;) {
    bool more = false;
    try {
      more = source->ReadLine(line);
    } catch (const LineTooLong& e) {  // never buffered whole: a corrupt line like any other
      ++stats.lines;
      ++line_number;
      Corrupt(e.what());
      continue;
    }
    if (!more) break;
    ++stats.lines;
    ++line_number;
    while (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files
    Tokenize(line, tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    try {
      if (HandleLine(tokens)) return true;
    } catch (const LineError& e) {
      Corrupt(e.what);
    }
  }
  return false;
}

bool CarmenReader::Impl::HandleLine(Tokens tok) {
  const Fields f(tok);
  const std::string_view type = tok[0];
  auto push_scan = [&](ParsedScan p) {
    const double t = p.scan.timestamp;
    Push(std::move(p.scan), t, p.has_odometry);
    return true;
  };
  if (type == "ODOM") {
    OdometryReading odom = ParseOdom(f);
    Push(odom, odom.timestamp, false);
    return true;
  }
  if (type == "FLASER") return push_scan(ParseOldLaser(f, Mount::kFront));
  if (type == "RLASER") return push_scan(ParseOldLaser(f, Mount::kRear));
  if (auto k = NumberedName(type, "ROBOTLASER")) return push_scan(ParseRobotLaser(f, MountForLaserNumber(*k)));
  if (auto k = NumberedName(type, "RAWLASER")) return push_scan(ParseRawLaser(f, MountForLaserNumber(*k)));
  if (type == "PARAM") {
    ParseParam(f);
    ++stats.params;
    return false;
  }
  ++stats.ignored_unknown;  // SYNC, TRUEPOS, LASER3, ... and names we do not know
  if (auto it = stats.unknown_by_type.find(type); it != stats.unknown_by_type.end()) {
    ++it->second;
  } else if (stats.unknown_by_type.size() < kMaxUnknownTypes) {
    stats.unknown_by_type.emplace(type, 1);
  }
  return false;
}

void CarmenReader::Impl::Push(LogRecord record, double t, bool has_odometry) {
  if (t < last_released) {
    ++stats.dropped_late;
    Note("record at " + std::to_string(t) + " is older than records already released (reorder window " +
         std::to_string(options.reorder_window_s) + " s too small?); dropped");
    return;
  }
  ++(std::holds_alternative<LaserScan>(record) ? stats.scans : stats.odometry);
  newest = std::max(newest, t);
  heap.push_back({t, seq++, std::move(record), has_odometry});
  std::push_heap(heap.begin(), heap.end(), Later);
}

// Records leave in time order, which the repair needs: a scan continues from the ODOM before it.
void CarmenReader::Impl::Repair(Entry& e) {
  if (auto* odom = std::get_if<OdometryReading>(&e.record)) {
    odometry_repair.Apply(*odom);
    stats.repaired_odometry_steps = odometry_repair.repaired_steps();
  } else if (e.has_odometry) {
    odometry_repair.Apply(std::get<LaserScan>(e.record));
  }
}

void CarmenReader::Impl::Note(const std::string& what) {
  if (stats.first_errors.size() < kMaxReportedErrors)
    stats.first_errors.push_back(name + ":" + std::to_string(line_number) + ": " + what);
}

void CarmenReader::Impl::Corrupt(const std::string& what) {
  if (options.strict) throw CarmenParseError(name + ":" + std::to_string(line_number) + ": " + what);
  ++stats.skipped_corrupt;
  Note(what);
}

// ODOM x y theta tv rv accel <trailer>
OdometryReading CarmenReader::Impl::ParseOdom(const Fields& f) const {
  f.ExpectSize(10, "x y theta tv rv accel ipc_timestamp hostname logger_timestamp");
  OdometryReading odom;
  odom.pose = f.PoseAt(1, "pose");
  odom.translational_velocity = f.Number(4, "tv");
  odom.rotational_velocity = f.Number(5, "rv");
  f.Number(6, "accel");
  ReadTrailer(f, odom.timestamp, nullptr);
  return odom;
}

// FLASER n r1..rn [laser_x laser_y laser_theta robot_x robot_y robot_theta] <trailer>
ParsedScan CarmenReader::Impl::ParseOldLaser(const Fields& f, Mount mount) const {
  const std::size_t n = f.Count(1, "beam count");
  const bool with_poses = f.size() == n + 11;
  if (!with_poses && f.size() != n + 5)
    f.Fail("n=" + std::to_string(n) + " needs " + std::to_string(n + 11) + " tokens (or " + std::to_string(n + 5) +
           " without poses), got " + std::to_string(f.size()) + (f.size() < n + 5 ? " (truncated line?)" : ""));
  ParsedScan p;
  LaserScan& s = p.scan;
  ReadRanges(f, 2, n, s);
  const bool rear = mount == Mount::kRear;
  s.angle_increment = OldFormatResolution(n, rear ? params.rear_resolution : params.front_resolution);
  s.angle_min = OldFormatStartAngle(n, s.angle_increment);
  s.max_range = MaxRange(std::nullopt, mount, params, options.default_max_range);
  const std::optional<double> param_x = OffsetParam(mount, params);
  if (with_poses) {
    const Pose2D laser = f.PoseAt(2 + n, "laser pose"), robot = f.PoseAt(5 + n, "robot pose");
    s.sensor_offset = MountOffset(mount, param_x, &laser, &robot);
    s.odometry = robot;  // the second triple is the robot's raw odometry (protocol §8)
    p.has_odometry = true;
  } else {
    s.sensor_offset = MountOffset(mount, param_x, nullptr, nullptr);
  }
  ReadTrailer(f, s.timestamp, &s.timestamp_text);
  return p;
}

// ROBOTLASERk <head> laser_pose robot_pose tv rv forward_safety side_safety turn_axis <trailer>
ParsedScan CarmenReader::Impl::ParseRobotLaser(const Fields& f, Mount mount) const {
  ParsedScan p;
  LaserScan& s = p.scan;
  double max_range = 0.0;
  const std::size_t i = ReadNewLaserHead(f, 24, s, max_range);
  const Pose2D laser = f.PoseAt(i, "laser pose"), robot = f.PoseAt(i + 3, "robot pose");
  for (std::size_t j = i + 6; j < i + 11; ++j) f.Number(j, "velocity/safety field");
  const std::optional<double> param_x = OffsetParam(mount, params);
  s.sensor_offset = MountOffset(mount, param_x, &laser, &robot);
  s.odometry = robot;
  s.max_range = MaxRange(max_range, mount, params, options.default_max_range);
  p.has_odometry = true;
  ReadTrailer(f, s.timestamp, &s.timestamp_text);
  return p;
}

// RAWLASERk <head> <trailer>: the driver's output, no poses.
ParsedScan CarmenReader::Impl::ParseRawLaser(const Fields& f, Mount mount) const {
  ParsedScan p;
  LaserScan& s = p.scan;
  double max_range = 0.0;
  ReadNewLaserHead(f, 13, s, max_range);
  const std::optional<double> param_x = OffsetParam(mount, params);
  s.sensor_offset = MountOffset(mount, param_x, nullptr, nullptr);
  s.max_range = MaxRange(max_range, mount, params, options.default_max_range);
  ReadTrailer(f, s.timestamp, &s.timestamp_text);
  return p;
}

// PARAM name value... [ipc_timestamp hostname logger_timestamp]. The trailer varies (the Intel log
// writes "name value hostname logger_timestamp", older loggers may write none) and values may hold
// spaces; every parameter used here is one number, the first token after the name, so the trailer
// is never needed. Parameters apply in file order, to the laser lines parsed after them.
void CarmenReader::Impl::ParseParam(const Fields& f) {
  if (f.size() < 3) f.Fail("needs a name and a value");
  const std::string_view key = f[1];
  auto number = [&](const char* what, bool positive) {
    const double v = f.Finite(2, what);
    if (positive && v <= 0.0) f.Fail(std::string(what) + " must be positive: " + std::string(f[2]));
    return v;
  };
  if (key == "robot_frontlaser_offset") params.front_offset = number("robot_frontlaser_offset", false);
  else if (key == "robot_rearlaser_offset") params.rear_offset = number("robot_rearlaser_offset", false);
  else if (key == "robot_front_laser_max") params.front_max = number("robot_front_laser_max", true);
  else if (key == "robot_rear_laser_max") params.rear_max = number("robot_rear_laser_max", true);
  else if (key == "laser_front_laser_resolution") params.front_resolution = number("laser_front_laser_resolution", true) * kDeg;
  else if (key == "laser_rear_laser_resolution") params.rear_resolution = number("laser_rear_laser_resolution", true) * kDeg;
}

// ---------------------------------------------------------------------------------------------

CarmenReader::CarmenReader(const std::string& path, CarmenReaderOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->source = OpenPath(path);
  impl_->name = path;
  impl_->options = options;
}

CarmenReader::CarmenReader(std::istream& in, std::string name, CarmenReaderOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->source = std::make_unique<StreamSource>(in);
  impl_->name = std::move(name);
  impl_->options = options;
}

CarmenReader::~CarmenReader() = default;
CarmenReader::CarmenReader(CarmenReader&&) noexcept = default;
CarmenReader& CarmenReader::operator=(CarmenReader&&) noexcept = default;

std::optional<LogRecord> CarmenReader::Next() { return impl_->Next(); }
const CarmenReadStats& CarmenReader::stats() const { return impl_->stats; }
double CarmenReader::progress() const { return impl_->source->Progress(); }
bool CarmenReader::last_scan_has_odometry() const { return impl_->last_has_odometry; }

// ---------------------------------------------------------------------------------------------

ScanStream::ScanStream(CarmenReader& reader, double max_odometry_wait_s)
    : reader_(reader), max_wait_s_(max_odometry_wait_s) {}

std::optional<LaserScan> ScanStream::Next() {
  for (;;) {
    if (!pending_.empty() && pending_.front().resolved) {
      LaserScan scan = std::move(pending_.front().scan);
      pending_.pop_front();
      return scan;
    }
    if (eof_) {
      if (pending_.empty()) return std::nullopt;
      Hold(pending_.front());  // no ODOM after it: hold the last one before
      continue;
    }
    std::optional<LogRecord> record = reader_.Next();
    if (!record) {
      eof_ = true;
      continue;
    }
    if (const auto* odom = std::get_if<OdometryReading>(&*record)) {
      ExpireWaiting(odom->timestamp);
      OnOdometry(*odom);
      continue;
    }
    LaserScan& scan = std::get<LaserScan>(*record);
    ExpireWaiting(scan.timestamp);
    const bool has_odometry = reader_.last_scan_has_odometry();
    pending_.push_back({std::move(scan), has_odometry, has_odometry ? std::nullopt : last_odom_});
  }
}

// Records arrive in time order, so this ODOM is the first one at or after every waiting scan.
void ScanStream::OnOdometry(const OdometryReading& odom) {
  for (Pending& p : pending_) {
    if (p.resolved) continue;
    if (p.before && odom.timestamp > p.before->timestamp) {
      const double t = (p.scan.timestamp - p.before->timestamp) / (odom.timestamp - p.before->timestamp);
      p.scan.odometry = Interpolate(p.before->pose, odom.pose, std::clamp(t, 0.0, 1.0));
    } else {
      p.scan.odometry = odom.pose;  // before the first ODOM: hold it
    }
    p.resolved = true;
  }
  last_odom_ = odom;
}

void ScanStream::ExpireWaiting(double now) {
  for (Pending& p : pending_) {
    if (now - p.scan.timestamp <= max_wait_s_) break;  // pending_ is in time order
    if (!p.resolved) Hold(p);
  }
}

void ScanStream::Hold(Pending& p) {
  if (p.before) {
    p.scan.odometry = p.before->pose;
  } else {
    p.scan.odometry = Pose2D();
    ++scans_without_odometry_;
  }
  p.resolved = true;
}

}  // namespace pslam
