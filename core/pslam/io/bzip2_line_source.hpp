#pragma once
// Lines of a bzip2-compressed file (a .clf.bz2 log), decompressed with libbz2 as they are read.
#include <bzlib.h>

#include <cstddef>
#include <fstream>
#include <string>
#include <vector>

#include "pslam/io/line_source.hpp"

namespace pslam {

class Bzip2LineSource : public LineSource {
 public:
  // Throws std::runtime_error naming the path if it cannot be opened. Concatenated streams (as
  // pbzip2 writes) are read one after the other; bytes after the last stream that are not one are
  // ignored, as bunzip2 does. Corrupt or truncated data throws std::runtime_error when reached: a
  // cut-off bzip2 block loses up to 900 kB of the log, too much to pass over as one bad line.
  explicit Bzip2LineSource(const std::string& path);
  ~Bzip2LineSource() override;
  Bzip2LineSource(const Bzip2LineSource&) = delete;
  Bzip2LineSource& operator=(const Bzip2LineSource&) = delete;

  bool ReadLine(std::string& line) override;
  double Progress() const override;

 private:
  bool Refill();  // decompresses the next piece into out_; false at the end of the data

  std::string path_;
  std::ifstream file_;
  double compressed_size_ = 0.0, compressed_read_ = 0.0;
  bz_stream stream_{};
  bool stream_open_ = false, input_eof_ = false, done_ = false;
  std::size_t streams_ = 0;  // streams started so far
  std::vector<char> in_, out_;
  std::size_t out_begin_ = 0, out_end_ = 0;  // the part of out_ not yet returned
};

}  // namespace pslam
