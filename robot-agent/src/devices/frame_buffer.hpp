#pragma once
// Receive buffer shared by the P2OS and SICK frame parsers: bytes as they came off the serial line,
// plus the arrival time of each chunk, so that a frame can be stamped with the time its first byte
// arrived (ARIA's rule) rather than the time it was complete.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

namespace pslam::agent {

class FrameBuffer {
 public:
  void Push(std::span<const std::uint8_t> bytes, double arrival_time) {
    if (bytes.empty()) return;
    chunks_.push_back({consumed_ + bytes_.size(), arrival_time});
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
  }
  std::size_t size() const { return bytes_.size(); }
  std::uint8_t operator[](std::size_t i) const { return bytes_[i]; }
  std::span<const std::uint8_t> View(std::size_t offset, std::size_t length) const {
    return {bytes_.data() + offset, length};
  }
  // Arrival time of the byte at 'offset' (relative to the current front).
  double TimeOf(std::size_t offset) const {
    const std::uint64_t absolute = consumed_ + offset;
    double t = chunks_.empty() ? 0.0 : chunks_.front().time;
    for (const auto& c : chunks_) {
      if (c.first_byte > absolute) break;
      t = c.time;
    }
    return t;
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
  struct Chunk {
    std::uint64_t first_byte;  // absolute stream offset of the chunk's first byte
    double time;
  };
  std::vector<std::uint8_t> bytes_;
  std::deque<Chunk> chunks_;
  std::uint64_t consumed_ = 0;
};

}  // namespace pslam::agent
