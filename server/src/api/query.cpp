#include "api/query.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "service/api_error.hpp"

namespace pslam::server {
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::optional<std::string> PercentDecode(std::string_view text, bool plus_is_space) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '%') {
      if (i + 2 >= text.size()) return std::nullopt;  // needs two hex digits
      const int hi = HexValue(text[i + 1]), lo = HexValue(text[i + 2]);
      if (hi < 0 || lo < 0) return std::nullopt;
      c = static_cast<char>(hi * 16 + lo);
      i += 2;
    } else if (c == '+' && plus_is_space) {
      c = ' ';
    }
    if (c == '\0') return std::nullopt;
    out += c;
  }
  return out;
}

std::optional<Target> ParseTarget(std::string_view target) {
  if (target.empty() || target.front() != '/') return std::nullopt;
  const std::size_t q = target.find('?');
  Target t;
  const auto path = PercentDecode(target.substr(0, q), false);
  if (!path) return std::nullopt;
  t.path = *path;
  if (q == std::string_view::npos) return t;
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const std::size_t amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
    if (pair.empty()) continue;
    const std::size_t eq = pair.find('=');
    const auto key = PercentDecode(pair.substr(0, eq), true);
    const auto value = PercentDecode(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1), true);
    if (!key || !value) return std::nullopt;
    t.query[*key] = *value;
  }
  return t;
}

std::optional<double> QueryNumber(const std::map<std::string, std::string>& query, const std::string& name) {
  const auto it = query.find(name);
  if (it == query.end()) return std::nullopt;
  const std::string& s = it->second;
  char* end = nullptr;
  const double v = s.empty() ? NAN : std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
    throw ApiError::BadRequest("query parameter '" + name + "' must be a finite number");
  }
  return v;
}

namespace {

long long Integer(const std::string& s, const std::string& what, long long min, long long max) {
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || v < min || v > max) {
    throw ApiError::BadRequest(what + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  }
  return v;
}

}  // namespace

std::optional<long long> QueryInteger(const std::map<std::string, std::string>& query, const std::string& name,
                                      long long min, long long max) {
  const auto it = query.find(name);
  if (it == query.end()) return std::nullopt;
  return Integer(it->second, "query parameter '" + name + "'", min, max);
}

long long PathInteger(const std::string& value, const std::string& name, long long min, long long max) {
  return Integer(value, "path parameter '" + name + "'", min, max);
}

std::optional<std::string> QueryString(const std::map<std::string, std::string>& query, const std::string& name) {
  const auto it = query.find(name);
  if (it == query.end()) return std::nullopt;
  if (it->second.size() > 256) throw ApiError::BadRequest("query parameter '" + name + "' is too long");
  return it->second;
}

std::optional<std::string> QueryChoice(const std::map<std::string, std::string>& query, const std::string& name,
                                       const std::vector<std::string>& choices) {
  const auto value = QueryString(query, name);
  if (!value) return value;
  for (const std::string& c : choices) {
    if (*value == c) return value;
  }
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i) list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  throw ApiError::BadRequest("query parameter '" + name + "' must be " + list);
}

}  // namespace pslam::server
