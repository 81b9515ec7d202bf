#include "pslam/io/bzip2_line_source.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace pslam {

Bzip2LineSource::Bzip2LineSource(const std::string& path)
    : path_(path), file_(path, std::ios::binary), in_(1 << 16), out_(1 << 17) {
  if (!file_) throw std::runtime_error("cannot open CARMEN log '" + path + "': " + std::strerror(errno));
  file_.seekg(0, std::ios::end);
  compressed_size_ = static_cast<double>(file_.tellg());
  file_.seekg(0);
}

Bzip2LineSource::~Bzip2LineSource() {
  if (stream_open_) BZ2_bzDecompressEnd(&stream_);
}

bool Bzip2LineSource::ReadLine(std::string& line) {
  line.clear();
  bool too_long = false;
  for (;;) {
    if (out_begin_ == out_end_ && !Refill()) {
      done_ = true;
      if (too_long) throw LineTooLong();
      return !line.empty();  // a last line without '\n'
    }
    const char* begin = out_.data() + out_begin_;
    const char* end = out_.data() + out_end_;
    const char* newline = std::find(begin, end, '\n');
    if (too_long || line.size() + static_cast<std::size_t>(newline - begin) > kMaxLineBytes) {
      too_long = true;  // skip to the end of the line without keeping it
      line.clear();
    } else {
      line.append(begin, newline);
    }
    out_begin_ = static_cast<std::size_t>(newline - out_.data());
    if (newline != end) {
      ++out_begin_;
      if (too_long) throw LineTooLong();
      return true;
    }
  }
}

double Bzip2LineSource::Progress() const {
  if (done_) return 1.0;
  if (compressed_size_ <= 0.0) return 0.0;
  return std::min(1.0, (compressed_read_ - static_cast<double>(stream_.avail_in)) / compressed_size_);
}

bool Bzip2LineSource::Refill() {
  for (;;) {
    if (stream_.avail_in == 0 && !input_eof_) {
      file_.read(in_.data(), static_cast<std::streamsize>(in_.size()));
      if (file_.bad()) throw std::runtime_error("cannot read CARMEN log '" + path_ + "'");
      const auto n = static_cast<std::size_t>(file_.gcount());
      compressed_read_ += static_cast<double>(n);
      stream_.next_in = in_.data();
      stream_.avail_in = static_cast<unsigned>(n);
      input_eof_ = !file_;  // a short read means the end of the file
    }
    if (!stream_open_) {
      if (stream_.avail_in == 0) return false;  // the file ended right after a complete stream
      stream_.bzalloc = nullptr;
      stream_.bzfree = nullptr;
      stream_.opaque = nullptr;
      if (BZ2_bzDecompressInit(&stream_, 0, 0) != BZ_OK) {
        throw std::runtime_error("CARMEN log '" + path_ + "': libbz2 could not start decompressing");
      }
      stream_open_ = true;
      ++streams_;
    }
    stream_.next_out = out_.data();
    stream_.avail_out = static_cast<unsigned>(out_.size());
    const int rc = BZ2_bzDecompress(&stream_);
    out_begin_ = 0;
    out_end_ = out_.size() - stream_.avail_out;
    if (rc == BZ_STREAM_END) {
      BZ2_bzDecompressEnd(&stream_);
      stream_open_ = false;  // another stream may follow
    } else if (rc == BZ_DATA_ERROR_MAGIC && streams_ > 1) {
      BZ2_bzDecompressEnd(&stream_);  // bytes after the last stream: ignored, as bunzip2 does
      stream_open_ = false;
      stream_.avail_in = 0;
      input_eof_ = true;
    } else if (rc != BZ_OK) {
      throw std::runtime_error("CARMEN log '" + path_ + "': corrupt bzip2 data (libbz2 error " + std::to_string(rc) +
                               ")");
    } else if (out_end_ == 0 && stream_.avail_in == 0 && input_eof_) {
      throw std::runtime_error("CARMEN log '" + path_ + "' ends inside a bzip2 stream (truncated file?)");
    }
    if (out_end_ > 0) return true;
  }
}

}  // namespace pslam
