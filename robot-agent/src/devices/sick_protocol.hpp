#pragma once
// Pure encode/decode of the SICK LMS-200 telegram protocol (shared/protocols/sick-lms200.md):
// framing (§2), the CRC-16 (§4), operating modes and baud codes (§3.1), the 0xB0 measured-values
// reply with its count word and measuring-mode dependent distance bits (§6.2, §7). No I/O here.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "devices/frame_buffer.hpp"

namespace pslam::agent::sick {

inline constexpr std::uint8_t kStx = 0x02;
inline constexpr std::uint8_t kAck = 0x06;
inline constexpr std::uint8_t kNak = 0x15;
inline constexpr std::uint8_t kHostToScanner = 0x00;
inline constexpr std::uint8_t kScannerToHost = 0x80;  // + scanner address
inline constexpr std::size_t kMaxTelegram = 812;      // a 401-value scan

enum Command : std::uint8_t {
  kReset = 0x10,
  kSwitchMode = 0x20,
  kRequestScan = 0x30,
  kStatus = 0x31,
  kType = 0x3A,
  kVariant = 0x3B,
  kReadConfig = 0x74,
  kWriteConfig = 0x77,
};
inline constexpr std::uint8_t kReplyOffset = 0x80;  // reply code = command + 0x80
inline constexpr std::uint8_t kScanReply = 0xB0;
inline constexpr std::uint8_t kNotAcknowledged = 0x92;

// Operating modes for command 0x20 (§3.1).
enum Mode : std::uint8_t {
  kModeInstallation = 0x00,
  kModeContinuous = 0x24,  // stream 0xB0 telegrams, one per scan
  kModePolled = 0x25,      // the default; also stops streaming
  kModeBaud38400 = 0x40,
  kModeBaud19200 = 0x41,
  kModeBaud9600 = 0x42,
  kModeBaud500k = 0x48,
};
// The 0x20 mode that switches the scanner to 'baud'; nullopt for a rate it does not support.
std::optional<std::uint8_t> BaudMode(int baud);
std::optional<int> BaudOfMode(std::uint8_t mode);

// §4: SICK's own CRC, generator 0x8005, word-wise over (previous byte, current byte).
std::uint16_t Crc16(std::span<const std::uint8_t> bytes);

// STX, address, LEN, body (command + data [+ status]), CRC low byte first.
std::vector<std::uint8_t> EncodeTelegram(std::uint8_t address, std::span<const std::uint8_t> body);
// Host to scanner: body = command + data.
std::vector<std::uint8_t> EncodeRequest(std::uint8_t command, std::span<const std::uint8_t> data = {});
// Scanner to host: body = reply code + data + status.
std::vector<std::uint8_t> EncodeReply(std::uint8_t reply, std::span<const std::uint8_t> data, std::uint8_t status = 0);

struct Telegram {
  std::uint8_t address = 0;
  std::uint8_t command = 0;             // command or reply code
  std::vector<std::uint8_t> data;       // between the code and the status byte (replies) / CRC (requests)
  std::uint8_t status = 0;              // replies only
  double time = 0.0;                    // arrival time of the STX byte
};

struct ParserStats {
  std::size_t telegrams = 0;
  std::size_t bad_crc = 0;        // framed telegrams whose CRC failed: dropped
  std::size_t skipped_bytes = 0;  // ACK/NAK bytes and line noise passed over while hunting for STX
  std::size_t acks = 0, naks = 0; // bare ACK/NAK bytes seen between telegrams
};

// Incremental receiver. 'replies' selects the direction: scanner->host telegrams (address 0x80..0x87,
// carrying a status byte) for the agent, host->scanner (address 0x00) for the scanner simulator.
// 0x02/0x80 also occur inside data, so a start is trusted only once LEN is plausible and the CRC
// checks; a failed CRC drops a single byte and the hunt resumes.
class TelegramParser {
 public:
  explicit TelegramParser(bool replies) : replies_(replies) {}
  // 'byte_seconds': see FrameBuffer::Push.
  void Push(std::span<const std::uint8_t> bytes, double arrival_time, double byte_seconds = 0.0) {
    buffer_.Push(bytes, arrival_time, byte_seconds);
  }
  std::optional<Telegram> Next();
  const ParserStats& stats() const { return stats_; }
  void Clear() { buffer_.Consume(buffer_.size()); }

 private:
  bool AddressOk(std::uint8_t a) const { return replies_ ? (a >= 0x80 && a <= 0x87) : a == kHostToScanner; }
  bool replies_;
  FrameBuffer buffer_;
  ParserStats stats_;
};

// Measuring modes that change the distance bits (§6.2); the factory default is 0x00.
struct RangeFormat {
  std::uint16_t distance_mask = 0x1FFF;
  double max_range_m = 8.191;  // with mm units
};
RangeFormat RangeFormatFor(std::uint8_t measuring_mode, std::uint8_t unit_code /*0 cm, 1 mm, 2 10 cm*/);

struct MeasuredScan {
  std::vector<float> ranges_m;  // NaN where the scanner reported no return
  bool partial = false;         // count word bit 13
  std::uint8_t unit_code = 1;
  double max_range_m = 0.0;
};
// Decodes the data of a 0xB0 reply with the given measuring mode; nullopt if the value count does
// not match the data length. Values of 0 and the reserved top of the range (within 10 units of the
// maximum) are "no return" (§6.2).
std::optional<MeasuredScan> DecodeScan(const Telegram& t, std::uint8_t measuring_mode);
// Data of a 0xB0 reply from raw values (scanner simulator and tests).
std::vector<std::uint8_t> EncodeScanData(std::span<const std::uint16_t> raw_values, std::uint8_t unit_code);

}  // namespace pslam::agent::sick
