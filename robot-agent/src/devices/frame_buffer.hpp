#pragma once
// Receive buffer shared by the P2OS and SICK frame parsers: bytes as they came off the serial line,
// plus the arrival time of each chunk, so that a frame can be stamped with the time its first byte
// arrived (ARIA's rule) rather than the time it was complete.
//
// A read returns whatever the driver holds, so on a busy machine one chunk can hold several frames.
// They came over the line one after another, not together: given the line's byte time, a byte is
// dated back from its chunk's arrival by the wire time of the bytes after it in that chunk, so
// frames read together keep distinct, increasing stamps.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <span>
#include <vector>

namespace pslam::agent {

// Seconds per byte on a serial line at 'baud' (10 bits a byte: start, 8 data, stop).
inline double LineByteSeconds(int baud) { return baud > 0 ? 10.0 / baud : 0.0; }

class FrameBuffer {
 public:
  // 'byte_seconds': the line's time per byte (LineByteSeconds); 0 dates nothing back.
  void Push(std::span<const std::uint8_t> bytes, double arrival_time, double byte_seconds = 0.0) {
    if (bytes.empty()) return;
    chunks_.push_back({consumed_ + bytes_.size(), arrival_time, byte_seconds});
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
  }
  std::size_t size() const { return bytes_.size(); }
  std::uint8_t operator[](std::size_t i) const { return bytes_[i]; }
  std::span<const std::uint8_t> View(std::size_t offset, std::size_t length) const {
    return {bytes_.data() + offset, length};
  }
  // Arrival time of the byte at 'offset' (relative to the current front).
  double TimeOf(std::size_t offset) const {
    if (chunks_.empty()) return 0.0;
    const std::uint64_t absolute = consumed_ + offset;
    return TimeIn(ChunkOf(absolute), absolute);
  }
  // Stamps the frame of 'length' bytes at the front and drops it. The stamp is the arrival of its
  // first byte, but never earlier than the frame before it plus that frame's time on the line: on
  // the wire a frame cannot begin before the one ahead of it is through, and a driver that hands
  // over bytes in bursts (a USB adapter, a pseudo-terminal) would otherwise let stamps run
  // backwards.
  double TakeFrame(std::size_t length) {
    double stamp = next_frame_earliest_, byte_seconds = 0.0;
    if (!chunks_.empty()) {
      const std::size_t i = ChunkOf(consumed_);
      stamp = std::max(stamp, TimeIn(i, consumed_));
      byte_seconds = chunks_[i].byte_seconds;
    }
    next_frame_earliest_ = stamp + static_cast<double>(length) * byte_seconds;
    Consume(length);
    return stamp;
  }
  // Drops 'n' bytes from the front.
  void Consume(std::size_t n) {
    bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(n));
    consumed_ += n;
    // Keep the chunk that holds the new front byte; forget the ones before it.
    while (chunks_.size() > 1 && chunks_[1].first_byte <= consumed_) chunks_.pop_front();
    if (bytes_.empty()) chunks_.clear();
  }

 private:
  // Arrival of the byte at stream offset 'absolute', which chunk i holds: the chunk's arrival less
  // the wire time of the bytes after it in that chunk.
  double TimeIn(std::size_t i, std::uint64_t absolute) const {
    const std::uint64_t chunk_end = i + 1 < chunks_.size() ? chunks_[i + 1].first_byte : consumed_ + bytes_.size();
    const std::uint64_t bytes_after = chunk_end > absolute + 1 ? chunk_end - absolute - 1 : 0;
    return chunks_[i].time - static_cast<double>(bytes_after) * chunks_[i].byte_seconds;
  }
  // Index of the chunk that holds the byte at stream offset 'absolute'.
  std::size_t ChunkOf(std::uint64_t absolute) const {
    std::size_t i = 0;
    while (i + 1 < chunks_.size() && chunks_[i + 1].first_byte <= absolute) ++i;
    return i;
  }

  struct Chunk {
    std::uint64_t first_byte;  // absolute stream offset of the chunk's first byte
    double time;
    double byte_seconds;
  };
  std::vector<std::uint8_t> bytes_;
  std::deque<Chunk> chunks_;
  std::uint64_t consumed_ = 0;
  double next_frame_earliest_ = -std::numeric_limits<double>::infinity();
};

}  // namespace pslam::agent
