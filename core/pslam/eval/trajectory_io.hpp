#pragma once
// Trajectory files: one pose per line, "timestamp x y theta" (metres, radians). The timestamp text
// is kept verbatim, so that a written trajectory names scans exactly as the log did
// ("976052857.337530"); a double printed back need not. Relations match stamps by time, though
// (relative_pose_error.hpp).
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct StampedPose {
  std::string stamp;  // timestamp text as read or given; written verbatim
  double time = 0.0;  // the same timestamp in seconds
  Pose2D pose;
};

// Seconds from a decimal timestamp text; nullopt unless the whole text is a finite number.
std::optional<double> ParseStampSeconds(std::string_view text);

// Reads text records of numbers, one a line; blank lines and lines starting with '#' are skipped.
// Each record must have exactly 'count' fields, all numbers (ParseStampSeconds); 'layout' names
// them for the error message. on_record gets the field texts and their values. Throws
// std::runtime_error with "name:line: ..." on any malformed line.
void ReadNumericRecords(std::istream& in, const std::string& name, std::size_t count, const char* layout,
                        const std::function<void(const std::vector<std::string>& text,
                                                 const std::vector<double>& values)>& on_record);

// Writes one line per pose: the stamp text (or 'time' with %.6f when the stamp is empty), then
// x y theta with %.6f. Throws std::runtime_error naming the file if it cannot be written.
void WriteTrajectory(const std::string& path, const std::vector<StampedPose>& poses);
void WriteTrajectory(std::ostream& out, const std::vector<StampedPose>& poses);

// Reads such a file; blank lines and lines starting with '#' are skipped. Throws
// std::runtime_error with "file:line: ..." on any malformed line.
std::vector<StampedPose> ReadTrajectory(const std::string& path);
std::vector<StampedPose> ReadTrajectory(std::istream& in, const std::string& name);

}  // namespace pslam
