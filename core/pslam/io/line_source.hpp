#pragma once
// Text input one line at a time, whatever the file is stored as (plain, gzip, bzip2); the CARMEN
// reader is written against this.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace pslam {

// No log line comes near this (a 1081-beam laser line is ~10 kB); a longer one is not buffered.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

// Thrown by ReadLine for a line longer than kMaxLineBytes, once the rest of that line has been
// skipped: the next ReadLine returns the line after it.
struct LineTooLong : std::runtime_error {
  LineTooLong() : std::runtime_error("line longer than " + std::to_string(kMaxLineBytes) + " bytes; skipped") {}
};

class LineSource {
 public:
  virtual ~LineSource() = default;
  virtual bool ReadLine(std::string& line) = 0;  // without the '\n'; false at the end
  virtual double Progress() const = 0;           // fraction of the input consumed in [0,1]; 0 if unknown
};

}  // namespace pslam
