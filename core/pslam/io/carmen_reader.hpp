#pragma once
// Streaming reader for CARMEN text logs (.log/.clf), see shared/protocols/carmen-log.md.
//
// CarmenReader yields ODOM and laser records in ipc_timestamp order (files are written in receive
// order, not acquisition order) through a bounded reorder buffer; ScanStream on top of it attaches
// odometry to every scan. Lines are read one at a time: memory is bounded by the reorder window.
#include <cstddef>
#include <deque>
#include <istream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

struct CarmenReaderOptions {
  bool strict = false;            // strict: the first corrupt line throws CarmenParseError; lenient: skip it and count it
  double reorder_window_s = 5.0;  // records are released in ipc_timestamp order once they are this far behind the newest seen
  double default_max_range = 0.0; // 0: from PARAM robot_front_laser_max / the record / the CARMEN convention (80 m)
  // Re-integrate ODOM steps whose pose moved forward while the logged velocity was backwards
  // (odometry_reversal.hpp); scan odometry follows.
  bool repair_reversed_odometry = true;
};

struct CarmenReadStats {
  std::size_t lines = 0, scans = 0, odometry = 0, params = 0, skipped_corrupt = 0, ignored_unknown = 0;
  // ignored_unknown by record name ("SYNC" -> 3); names past the first 16 are counted only in the total,
  // so that a file that is not a CARMEN log cannot grow this without bound.
  std::map<std::string, std::size_t, std::less<>> unknown_by_type;
  // Records that arrived more than reorder_window_s older than one already released: emitting them
  // would break time order, so they are dropped (and noted in first_errors). Not a corrupt line.
  std::size_t dropped_late = 0;
  // ODOM steps whose pose moved forward while the robot backed up, re-integrated backwards.
  std::size_t repaired_odometry_steps = 0;
  std::vector<std::string> first_errors;  // up to 20 messages "FILE:LINE: what is wrong"
};

class CarmenParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using LogRecord = std::variant<LaserScan, OdometryReading>;

class CarmenReader {
 public:
  // Throws std::runtime_error naming the path if it cannot be opened. bzip2 input (detected by its
  // magic bytes "BZh") is decompressed with libbz2. gzip input (magic bytes 1f 8b) is decompressed
  // with zlib when the io layer is built with PSLAM_HAVE_ZLIB (and linked to ZLIB::ZLIB); without
  // it a .gz file throws a clear error asking to gunzip it.
  explicit CarmenReader(const std::string& path, CarmenReaderOptions options = {});
  // Reads from a caller-owned stream that must outlive the reader; `name` is used in messages.
  CarmenReader(std::istream& in, std::string name, CarmenReaderOptions options = {});
  ~CarmenReader();
  CarmenReader(CarmenReader&&) noexcept;
  CarmenReader& operator=(CarmenReader&&) noexcept;

  std::optional<LogRecord> Next();  // next record in ipc_timestamp order; nullopt at the end
  const CarmenReadStats& stats() const;
  double progress() const;  // fraction of the input consumed in [0,1] (bytes), for a progress bar; 0 if unknown

  // True if the record last returned by Next() is a scan whose line carried the robot's odometry
  // pose (FLASER/RLASER with poses, ROBOTLASERk); its `odometry` is then that pose. False for
  // pose-less scans (RAWLASERk, old pose-less FLASER/RLASER) and for ODOM records.
  bool last_scan_has_odometry() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Yields laser scans (FLASER/RLASER/ROBOTLASERk/RAWLASERk/old pose-less FLASER) in time order with
// `odometry` filled: from the robot pose inside the laser line when it has one, otherwise interpolated
// (or, at the ends, held) from the ODOM records around the scan's time. Scans that cannot get odometry
// at all (no pose in the line and no ODOM in the log) are passed through with odometry at identity
// and counted in scans_without_odometry().
class ScanStream {
 public:
  // A pose-less scan waits for the next ODOM at most `max_odometry_wait_s` of log time; past that
  // it holds the previous ODOM (or identity if there was none). This bounds the memory on logs
  // without ODOM records.
  explicit ScanStream(CarmenReader& reader, double max_odometry_wait_s = 10.0);
  std::optional<LaserScan> Next();
  std::size_t scans_without_odometry() const { return scans_without_odometry_; }

 private:
  struct Pending {
    LaserScan scan;
    bool resolved = false;
    std::optional<OdometryReading> before;  // last ODOM at or before the scan's time
  };
  void OnOdometry(const OdometryReading& odom);
  void ExpireWaiting(double now);
  void Hold(Pending& p);

  CarmenReader& reader_;
  double max_wait_s_;
  std::deque<Pending> pending_;  // time order; only the front may leave, once resolved
  std::optional<OdometryReading> last_odom_;
  bool eof_ = false;
  std::size_t scans_without_odometry_ = 0;
};

}  // namespace pslam
