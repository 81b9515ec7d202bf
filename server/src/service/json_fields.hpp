#pragma once
// Strict reading of a JSON object into typed fields: a wrong type or an unknown key is an error
// that names the key (STYLE 6.8: reject unknown keys, name the offending one). Errors are thrown as
// ApiError(400); callers that speak another protocol catch and translate.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "service/api_error.hpp"

namespace pslam::server {

class JsonFields {
 public:
  // 'where' prefixes messages, e.g. "settings".
  JsonFields(const nlohmann::json& object, std::string where);

  std::optional<double> Number(const std::string& key);          // finite numbers only
  std::optional<std::int64_t> Integer(const std::string& key);
  std::optional<bool> Bool(const std::string& key);
  std::optional<std::string> String(const std::string& key, std::size_t max_length = 256);
  const nlohmann::json* Object(const std::string& key);
  const nlohmann::json* Array(const std::string& key);

  double NumberOr(const std::string& key, double fallback) { return Number(key).value_or(fallback); }
  double RequiredNumber(const std::string& key);
  std::int64_t RequiredInteger(const std::string& key);
  std::string RequiredString(const std::string& key, std::size_t max_length = 256);

  // Throws if the object has a key none of the getters asked for.
  void RejectUnknown() const;

  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const;

 private:
  const nlohmann::json* Find(const std::string& key);

  const nlohmann::json& object_;
  std::string where_;
  std::set<std::string> used_;
};

}  // namespace pslam::server
