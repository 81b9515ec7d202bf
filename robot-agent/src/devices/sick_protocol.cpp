#include "devices/sick_protocol.hpp"

#include <cmath>
#include <limits>

namespace pslam::agent::sick {

std::optional<std::uint8_t> BaudMode(int baud) {
  switch (baud) {
    case 9600: return kModeBaud9600;
    case 19200: return kModeBaud19200;
    case 38400: return kModeBaud38400;
    case 500000: return kModeBaud500k;
    default: return std::nullopt;
  }
}

std::optional<int> BaudOfMode(std::uint8_t mode) {
  switch (mode) {
    case kModeBaud9600: return 9600;
    case kModeBaud19200: return 19200;
    case kModeBaud38400: return 38400;
    case kModeBaud500k: return 500000;
    default: return std::nullopt;
  }
}

std::uint16_t Crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0;
  std::uint8_t prev = 0;
  for (std::uint8_t b : bytes) {
    if (crc & 0x8000) {
      crc = static_cast<std::uint16_t>((crc << 1) ^ 0x8005);
    } else {
      crc = static_cast<std::uint16_t>(crc << 1);
    }
    crc ^= static_cast<std::uint16_t>((prev << 8) | b);
    prev = b;
  }
  return crc;
}

std::vector<std::uint8_t> EncodeTelegram(std::uint8_t address, std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out;
  out.reserve(body.size() + 6);
  out.push_back(kStx);
  out.push_back(address);
  out.push_back(static_cast<std::uint8_t>(body.size() & 0xFF));
  out.push_back(static_cast<std::uint8_t>(body.size() >> 8));
  out.insert(out.end(), body.begin(), body.end());
  const std::uint16_t crc = Crc16(out);
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

std::vector<std::uint8_t> EncodeRequest(std::uint8_t command, std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> body{command};
  body.insert(body.end(), data.begin(), data.end());
  return EncodeTelegram(kHostToScanner, body);
}

std::vector<std::uint8_t> EncodeReply(std::uint8_t reply, std::span<const std::uint8_t> data, std::uint8_t status) {
  std::vector<std::uint8_t> body{reply};
  body.insert(body.end(), data.begin(), data.end());
  body.push_back(status);
  return EncodeTelegram(kScannerToHost, body);
}

std::optional<Telegram> TelegramParser::Next() {
  while (buffer_.size() >= 4) {
    if (buffer_[0] != kStx || !AddressOk(buffer_[1])) {
      if (buffer_[0] == kAck) ++stats_.acks;
      if (buffer_[0] == kNak) ++stats_.naks;
      buffer_.Consume(1);
      ++stats_.skipped_bytes;
      continue;
    }
    const std::size_t len = buffer_[2] | (buffer_[3] << 8);
    const std::size_t min_len = replies_ ? 2 : 1;  // code [+ status]
    if (len < min_len || len + 6 > kMaxTelegram) {
      buffer_.Consume(1);
      ++stats_.skipped_bytes;
      continue;
    }
    if (buffer_.size() < len + 6) return std::nullopt;  // partial: wait
    const std::uint16_t sent = static_cast<std::uint16_t>(buffer_[len + 4] | (buffer_[len + 5] << 8));
    if (Crc16(buffer_.View(0, len + 4)) != sent) {
      buffer_.Consume(1);  // the STX may have been a data byte: hunt again from the next byte
      ++stats_.bad_crc;
      continue;
    }
    Telegram t;
    t.address = buffer_[1];
    t.command = buffer_[4];
    const std::size_t data_len = len - min_len;
    const auto data = buffer_.View(5, data_len);
    t.data.assign(data.begin(), data.end());
    if (replies_) t.status = buffer_[4 + len - 1];
    t.time = buffer_.TakeFrame(len + 6);
    ++stats_.telegrams;
    return t;
  }
  return std::nullopt;
}

RangeFormat RangeFormatFor(std::uint8_t measuring_mode, std::uint8_t unit_code) {
  RangeFormat f;
  switch (measuring_mode) {
    case 0x03:
    case 0x04: f.distance_mask = 0x3FFF; break;
    case 0x05:
    case 0x06: f.distance_mask = 0x7FFF; break;
    case 0x0F: f.distance_mask = 0xFFFF; break;
    default: f.distance_mask = 0x1FFF; break;  // 0x00-0x02: the 8/80 m modes
  }
  const double unit_m = unit_code == 0 ? 0.01 : unit_code == 2 ? 0.1 : 0.001;
  f.max_range_m = f.distance_mask * unit_m;
  return f;
}

std::optional<MeasuredScan> DecodeScan(const Telegram& t, std::uint8_t measuring_mode) {
  if (t.command != kScanReply || t.data.size() < 2) return std::nullopt;
  const std::uint16_t count_word = static_cast<std::uint16_t>(t.data[0] | (t.data[1] << 8));
  const std::size_t n = count_word & 0x03FF;
  if (t.data.size() != 2 + 2 * n) return std::nullopt;
  MeasuredScan s;
  s.partial = (count_word & (1u << 13)) != 0;
  s.unit_code = static_cast<std::uint8_t>(count_word >> 14);
  const RangeFormat format = RangeFormatFor(measuring_mode, s.unit_code);
  const double unit_m = s.unit_code == 0 ? 0.01 : s.unit_code == 2 ? 0.1 : 0.001;
  s.max_range_m = format.max_range_m;
  const std::uint32_t reserved_from = format.distance_mask - 10u;  // error / no-echo codes
  s.ranges_m.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t raw = static_cast<std::uint16_t>(t.data[2 + 2 * i] | (t.data[3 + 2 * i] << 8));
    const std::uint32_t distance = raw & format.distance_mask;
    s.ranges_m.push_back(distance == 0 || distance >= reserved_from
                             ? std::numeric_limits<float>::quiet_NaN()
                             : static_cast<float>(distance * unit_m));
  }
  return s;
}

std::vector<std::uint8_t> EncodeScanData(std::span<const std::uint16_t> raw_values, std::uint8_t unit_code) {
  std::vector<std::uint8_t> data;
  data.reserve(2 + 2 * raw_values.size());
  const std::uint16_t count_word =
      static_cast<std::uint16_t>((raw_values.size() & 0x3FF) | (static_cast<unsigned>(unit_code & 0x3) << 14));
  data.push_back(static_cast<std::uint8_t>(count_word & 0xFF));
  data.push_back(static_cast<std::uint8_t>(count_word >> 8));
  for (std::uint16_t v : raw_values) {
    data.push_back(static_cast<std::uint8_t>(v & 0xFF));
    data.push_back(static_cast<std::uint8_t>(v >> 8));
  }
  return data;
}

}  // namespace pslam::agent::sick
