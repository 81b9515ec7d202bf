#include "link/spool.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/clock.hpp"
#include "common/log.hpp"
#include "link/crc32.hpp"

namespace pslam::agent {
namespace {

constexpr std::size_t kHeaderBytes = 16;
constexpr std::uint32_t kMaxPayload = 16u << 20;  // anything longer is a torn length field

std::runtime_error IoError(const std::string& what, const std::filesystem::path& path) {
  return std::runtime_error("spool: " + what + " " + path.string() + ": " + std::strerror(errno));
}

void PutU32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void PutU64(std::uint8_t* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint32_t GetU32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
std::uint64_t GetU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

std::uint32_t RecordCrc(const std::uint8_t* seq_bytes, std::span<const std::uint8_t> payload) {
  return Crc32(payload, Crc32({seq_bytes, 8}));
}

std::string SegmentName(std::uint64_t first_seq) {
  char name[48];
  std::snprintf(name, sizeof name, "seg-%020" PRIu64 ".spool", first_seq);
  return name;
}

std::optional<std::uint64_t> ParseSegmentName(const std::string& name) {
  std::uint64_t seq = 0;
  if (name.size() != 30 || name.rfind("seg-", 0) != 0 || name.substr(24) != ".spool") return std::nullopt;
  for (std::size_t i = 4; i < 24; ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    seq = seq * 10 + static_cast<std::uint64_t>(name[i] - '0');
  }
  return seq;
}

bool ReadExact(int fd, std::uint8_t* out, std::size_t n, std::uint64_t offset) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd, out + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    done += static_cast<std::size_t>(r);
  }
  return true;
}

void WriteAll(int fd, const std::uint8_t* data, std::size_t n, const std::filesystem::path& path) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd, data + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) throw IoError("cannot write", path);
    done += static_cast<std::size_t>(w);
  }
}

}  // namespace

Spool::Spool(SpoolOptions options) : options_(std::move(options)) {
  std::error_code ec;
  std::filesystem::create_directories(options_.directory, ec);
  if (ec) throw std::runtime_error("spool: cannot create " + options_.directory.string() + ": " + ec.message());
  Recover();
  OpenActive();
}

Spool::~Spool() {
  try {
    Sync();
  } catch (const std::exception& e) {
    PSLAM_LOG(kError) << e.what();
  }
  CloseReader();
  if (write_fd_ >= 0) ::close(write_fd_);
}

// Walks every segment in seq order, keeping the longest valid, gap-free run of records. The first
// invalid record is cut off with everything after it.
void Spool::Recover() {
  std::vector<std::pair<std::uint64_t, std::filesystem::path>> found;
  for (const auto& entry : std::filesystem::directory_iterator(options_.directory)) {
    if (const auto seq = ParseSegmentName(entry.path().filename().string())) found.emplace_back(*seq, entry.path());
  }
  std::sort(found.begin(), found.end());
  bool broken = false;
  std::uint64_t expected = found.empty() ? 1 : found.front().first;
  std::vector<std::uint8_t> payload;
  for (const auto& [first_seq, path] : found) {
    if (broken || first_seq != expected) {
      if (!broken) PSLAM_LOG(kWarning) << "spool: segment " << path << " does not continue the sequence; dropped";
      broken = true;
      ++recovery_.dropped_segments;
      std::filesystem::remove(path);
      continue;
    }
    const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) throw IoError("cannot open", path);
    struct stat st {};
    ::fstat(fd, &st);
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
    std::uint64_t offset = 0;
    std::uint64_t seq = first_seq;
    while (offset < size) {
      std::uint8_t header[kHeaderBytes];
      bool valid = offset + kHeaderBytes <= size && ReadExact(fd, header, kHeaderBytes, offset);
      std::uint32_t length = valid ? GetU32(header) : 0;
      valid = valid && length <= kMaxPayload && offset + kHeaderBytes + length <= size &&
              GetU64(header + 8) == seq;
      if (valid) {
        payload.resize(length);
        valid = ReadExact(fd, payload.data(), length, offset + kHeaderBytes) &&
                RecordCrc(header + 8, payload) == GetU32(header + 4);
      }
      if (!valid) {
        ++recovery_.torn_records;
        recovery_.truncated_bytes += size - offset;
        if (::ftruncate(fd, static_cast<off_t>(offset)) != 0) {
          ::close(fd);
          throw IoError("cannot truncate", path);
        }
        broken = true;
        break;
      }
      offset += kHeaderBytes + length;
      ++seq;
      ++recovery_.records;
    }
    ::close(fd);
    segments_.push_back({first_seq, seq, offset, path});
    bytes_ += offset;
    expected = seq;
  }
  // A truncated segment that is now empty and not the only one would leave a useless file behind.
  while (segments_.size() > 1 && segments_.back().bytes == 0) {
    std::filesystem::remove(segments_.back().path);
    segments_.pop_back();
  }
  recovery_.segments = segments_.size();
  if (!segments_.empty()) {
    next_seq_ = segments_.back().end_seq;
    acked_ = segments_.front().first_seq - 1;
  }
  if (recovery_.torn_records > 0 || recovery_.dropped_segments > 0) {
    PSLAM_LOG(kWarning) << "spool: cut a torn/corrupt tail of " << recovery_.truncated_bytes
                        << " bytes (records after seq " << next_seq_ - 1 << " were not written completely); "
                        << recovery_.dropped_segments << " later segment(s) dropped";
  }
}

void Spool::OpenActive() {
  if (segments_.empty()) {
    segments_.push_back({next_seq_, next_seq_, 0, options_.directory / SegmentName(next_seq_)});
  }
  const auto& active = segments_.back();
  write_fd_ = ::open(active.path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (write_fd_ < 0) throw IoError("cannot open", active.path);
}

void Spool::RollSegment() {
  if (::fdatasync(write_fd_) != 0) throw IoError("cannot sync", segments_.back().path);
  ::close(write_fd_);
  write_fd_ = -1;
  segments_.push_back({next_seq_, next_seq_, 0, options_.directory / SegmentName(next_seq_)});
  OpenActive();
  DeleteAckedSegments();
}

bool Spool::WouldFit(std::size_t payload_bytes) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return bytes_ + kHeaderBytes + payload_bytes <= options_.max_bytes;
}

std::optional<std::uint64_t> Spool::Append(std::span<const std::uint8_t> payload) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const std::uint64_t record_bytes = kHeaderBytes + payload.size();
  if (bytes_ + record_bytes > options_.max_bytes) {
    ++refused_full_;
    return std::nullopt;
  }
  if (segments_.back().bytes > 0 && segments_.back().bytes + record_bytes > options_.segment_bytes) RollSegment();

  const std::uint64_t seq = next_seq_;
  // One write() per record: a crash leaves at worst one partial record at the end.
  std::vector<std::uint8_t> record(record_bytes);
  PutU32(record.data(), static_cast<std::uint32_t>(payload.size()));
  PutU64(record.data() + 8, seq);
  std::copy(payload.begin(), payload.end(), record.begin() + kHeaderBytes);
  PutU32(record.data() + 4, RecordCrc(record.data() + 8, payload));
  WriteAll(write_fd_, record.data(), record.size(), segments_.back().path);

  segments_.back().bytes += record_bytes;
  segments_.back().end_seq = seq + 1;
  bytes_ += record_bytes;
  ++next_seq_;
  dirty_ = true;
  const double now = AgentClock::Now();
  if (now - last_sync_ >= options_.sync_interval_s) {
    if (::fdatasync(write_fd_) != 0) throw IoError("cannot sync", segments_.back().path);
    last_sync_ = now;
    dirty_ = false;
  }
  return seq;
}

void Spool::Sync() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (write_fd_ >= 0 && dirty_) {
    if (::fdatasync(write_fd_) != 0) throw IoError("cannot sync", segments_.back().path);
    dirty_ = false;
    last_sync_ = AgentClock::Now();
  }
}

void Spool::Acknowledge(std::uint64_t seq) {
  const std::lock_guard<std::mutex> lock(mutex_);
  seq = std::min(seq, next_seq_ - 1);  // an ack beyond what we wrote belongs to another spool
  if (seq <= acked_) return;
  acked_ = seq;
  DeleteAckedSegments();
}

void Spool::DropAll() {
  const std::lock_guard<std::mutex> lock(mutex_);
  acked_ = next_seq_ - 1;
  if (segments_.back().bytes > 0) {
    RollSegment();  // deletes the acknowledged segments, now every older one
  } else {
    DeleteAckedSegments();
  }
}

void Spool::DeleteAckedSegments() {
  while (segments_.size() > 1 && segments_.front().end_seq <= acked_ + 1) {
    if (read_fd_ >= 0 && read_segment_first_ == segments_.front().first_seq) CloseReader();
    std::error_code ec;
    std::filesystem::remove(segments_.front().path, ec);
    if (ec) PSLAM_LOG(kWarning) << "spool: cannot delete " << segments_.front().path << ": " << ec.message();
    bytes_ -= segments_.front().bytes;
    segments_.pop_front();
  }
}

void Spool::CloseReader() {
  if (read_fd_ >= 0) ::close(read_fd_);
  read_fd_ = -1;
}

std::optional<SpoolRecord> Spool::Read(std::uint64_t seq) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (seq <= acked_ || seq >= next_seq_) return std::nullopt;
  auto it = std::upper_bound(segments_.begin(), segments_.end(), seq,
                             [](std::uint64_t s, const Segment& seg) { return s < seg.first_seq; });
  if (it == segments_.begin()) return std::nullopt;
  const Segment& segment = *std::prev(it);
  if (read_fd_ < 0 || read_segment_first_ != segment.first_seq || read_seq_ > seq) {
    CloseReader();
    read_fd_ = ::open(segment.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (read_fd_ < 0) throw IoError("cannot open", segment.path);
    read_segment_first_ = segment.first_seq;
    read_offset_ = 0;
    read_seq_ = segment.first_seq;
  }
  std::uint8_t header[kHeaderBytes];
  while (true) {
    if (!ReadExact(read_fd_, header, kHeaderBytes, read_offset_)) {
      throw std::runtime_error("spool: record " + std::to_string(read_seq_) + " is missing from " + segment.path.string());
    }
    const std::uint32_t length = GetU32(header);
    if (read_seq_ == seq) {
      SpoolRecord r{seq, std::vector<std::uint8_t>(length)};
      if (!ReadExact(read_fd_, r.payload.data(), length, read_offset_ + kHeaderBytes) ||
          RecordCrc(header + 8, r.payload) != GetU32(header + 4)) {
        throw std::runtime_error("spool: record " + std::to_string(seq) + " in " + segment.path.string() +
                                 " is corrupt (disk error?)");
      }
      read_offset_ += kHeaderBytes + length;
      ++read_seq_;
      return r;
    }
    read_offset_ += kHeaderBytes + length;  // skip forward to 'seq'
    ++read_seq_;
  }
}

std::uint64_t Spool::acked_seq() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return acked_;
}

std::uint64_t Spool::next_seq() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return next_seq_;
}

bool Spool::empty_of_unacked() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return acked_ + 1 >= next_seq_;
}

SpoolStats Spool::stats() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  SpoolStats s;
  s.first_unacked_seq = acked_ + 1;
  s.next_seq = next_seq_;
  s.unacked_records = next_seq_ - 1 - acked_;
  s.bytes = bytes_;
  s.max_bytes = options_.max_bytes;
  s.refused_full = refused_full_;
  s.segments = segments_.size();
  return s;
}

}  // namespace pslam::agent
