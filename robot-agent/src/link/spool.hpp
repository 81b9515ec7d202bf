#pragma once
// The on-disk spool: every message the agent produces is appended here first, under a sequence
// number, and leaves only when the server acknowledges it (cumulatively). After a link drop the
// link resends from the oldest unacknowledged record; after a crash or power cut the agent reopens
// the spool and carries on.
//
// Layout: a directory of segment files "seg-<first seq, 20 digits>.spool", each a run of records
//   u32 payload length | u32 CRC-32 of (seq bytes + payload) | u64 seq | payload
// (little-endian). A torn last record (length past the end of file, bad CRC, or a seq that breaks
// the run) is detected on Open, truncated away and counted, never resent. Whole segments are
// deleted once all their records are acknowledged; the newest segment is always kept so that the
// sequence numbering survives a restart.
//
// Size is bounded: Append() refuses a record that would push the spool over max_bytes (the caller
// counts and reports it; a live sensor cannot wait, a log replay can).
//
// Durability: records are written with write() at once and fdatasync()ed at most every
// sync_interval_s (and on Sync()), so a power cut loses at most that window, and what it loses is a
// clean tail cut by the torn-record check.
//
// Thread-safe: the agent thread appends while the link thread reads and acknowledges.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

namespace pslam::agent {

struct SpoolOptions {
  std::filesystem::path directory;
  std::uint64_t max_bytes = 256ull << 20;     // about 4.5 h of 181-beam scans at 75 Hz
  std::uint64_t segment_bytes = 4ull << 20;   // deletion granularity
  double sync_interval_s = 0.2;
};

struct SpoolRecord {
  std::uint64_t seq = 0;
  std::vector<std::uint8_t> payload;
};

// What Open() found and repaired.
struct SpoolRecovery {
  std::size_t segments = 0;
  std::size_t records = 0;           // valid records kept
  std::size_t torn_records = 0;      // invalid records cut off (normally 0 or 1: the torn tail)
  std::uint64_t truncated_bytes = 0; // bytes removed by the cut
  std::size_t dropped_segments = 0;  // later segments removed because the run was broken before them
};

struct SpoolStats {
  std::uint64_t first_unacked_seq = 0;
  std::uint64_t next_seq = 0;
  std::uint64_t unacked_records = 0;
  std::uint64_t bytes = 0;
  std::uint64_t max_bytes = 0;
  std::uint64_t refused_full = 0;  // Append() calls refused because the spool was full
  std::size_t segments = 0;
};

class Spool {
 public:
  // Opens (creating if needed) the spool directory and recovers it. Throws std::runtime_error on
  // I/O errors.
  explicit Spool(SpoolOptions options);
  ~Spool();
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;

  const SpoolRecovery& recovery() const { return recovery_; }

  // Appends a record and returns its sequence number, or nullopt if the spool is full.
  // Throws std::runtime_error on a write error (disk gone).
  std::optional<std::uint64_t> Append(std::span<const std::uint8_t> payload);
  bool WouldFit(std::size_t payload_bytes) const;

  // Everything with seq <= 'seq' is acknowledged (cumulative; smaller values are ignored).
  void Acknowledge(std::uint64_t seq);
  std::uint64_t acked_seq() const;
  // Acknowledges everything written, durably: the records leave the disk (a fresh segment keeps the
  // numbering), so a later run does not send them again. For a session that is over.
  void DropAll();

  // Reads the record 'seq' (it must be unacknowledged and already appended); nullopt otherwise.
  // Sequential reads are served from an open file position, so the link's "next record" is cheap.
  std::optional<SpoolRecord> Read(std::uint64_t seq);

  std::uint64_t next_seq() const;
  bool empty_of_unacked() const;
  SpoolStats stats() const;
  void Sync();

 private:
  struct Segment {
    std::uint64_t first_seq = 0;
    std::uint64_t end_seq = 0;   // one past the last record
    std::uint64_t bytes = 0;
    std::filesystem::path path;
  };
  void Recover();
  void OpenActive();
  void RollSegment();
  void DeleteAckedSegments();
  void CloseReader();

  SpoolOptions options_;
  SpoolRecovery recovery_;
  mutable std::mutex mutex_;
  std::deque<Segment> segments_;
  std::uint64_t next_seq_ = 1;
  std::uint64_t acked_ = 0;
  std::uint64_t bytes_ = 0;
  std::uint64_t refused_full_ = 0;
  int write_fd_ = -1;
  double last_sync_ = 0.0;
  bool dirty_ = false;
  // Sequential read position: file, offset and the seq of the record found there.
  int read_fd_ = -1;
  std::uint64_t read_segment_first_ = 0;
  std::uint64_t read_offset_ = 0;
  std::uint64_t read_seq_ = 0;
};

}  // namespace pslam::agent
