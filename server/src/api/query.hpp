#pragma once
// URL targets: percent-decoding, the query string, and strict conversion of query values (a value
// that is not entirely a number is a 400, never silently 0).
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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
// A value that must be one of 'choices' (a filter on an enumerated field: a typo is a 400, not an
// empty list).
std::optional<std::string> QueryChoice(const std::map<std::string, std::string>& query, const std::string& name,
                                       const std::vector<std::string>& choices);
// A path segment that must be an integer in [min, max]; throws ApiError(400) naming it as a path parameter.
long long PathInteger(const std::string& value, const std::string& name, long long min, long long max);

}  // namespace pslam::server
