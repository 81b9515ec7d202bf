#pragma once
// URL targets: percent-decoding, the query string, and strict conversion of query values (a value
// that is not entirely a number is a 400, never silently 0).
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace pslam::server {

// nullopt if 'text' has a malformed escape or decodes to a NUL byte.
std::optional<std::string> PercentDecode(std::string_view text, bool plus_is_space);

struct Target {
  std::string path;
  std::map<std::string, std::string> query;
};
// nullopt if the target is not an absolute path or does not decode.
std::optional<Target> ParseTarget(std::string_view target);

// Query values; each throws ApiError(400) naming the parameter on a bad value.
std::optional<double> QueryNumber(const std::map<std::string, std::string>& query, const std::string& name);
std::optional<long long> QueryInteger(const std::map<std::string, std::string>& query, const std::string& name,
                                      long long min, long long max);
std::optional<std::string> QueryString(const std::map<std::string, std::string>& query, const std::string& name);

}  // namespace pslam::server
