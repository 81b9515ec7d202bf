#pragma once
// Text input one line at a time, whatever the file is stored as (plain, gzip, bzip2); the CARMEN
// reader is written against this.
#include <string>

namespace pslam {

class LineSource {
 public:
  virtual ~LineSource() = default;
  virtual bool ReadLine(std::string& line) = 0;  // without the '\n'; false at the end
  virtual double Progress() const = 0;           // fraction of the input consumed in [0,1]; 0 if unknown
};

}  // namespace pslam
