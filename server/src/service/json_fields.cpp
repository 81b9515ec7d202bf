#include "service/json_fields.hpp"

namespace pslam::server {

JsonFields::JsonFields(const nlohmann::json& object, std::string where) : object_(object), where_(std::move(where)) {
  if (!object_.is_object()) throw ApiError::BadRequest(where_ + " must be a JSON object");
}

void JsonFields::Fail(const std::string& key, const std::string& problem) const {
  throw ApiError::BadRequest(where_ + "." + key + " " + problem);
}

const nlohmann::json* JsonFields::Find(const std::string& key) {
  used_.insert(key);
  const auto it = object_.find(key);
  if (it == object_.end() || it->is_null()) return nullptr;
  return &*it;
}

std::optional<double> JsonFields::Number(const std::string& key) {
  const nlohmann::json* v = Find(key);
  if (!v) return std::nullopt;
  if (!v->is_number()) Fail(key, "must be a number");
  const double d = v->get<double>();
  if (!std::isfinite(d)) Fail(key, "must be finite");
  return d;
}

std::optional<std::int64_t> JsonFields::Integer(const std::string& key) {
  const nlohmann::json* v = Find(key);
  if (!v) return std::nullopt;
  if (v->is_number_unsigned()) {
    if (v->get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) Fail(key, "is too large");
    return static_cast<std::int64_t>(v->get<std::uint64_t>());
  }
  if (!v->is_number_integer()) Fail(key, "must be an integer");
  return v->get<std::int64_t>();
}

std::optional<bool> JsonFields::Bool(const std::string& key) {
  const nlohmann::json* v = Find(key);
  if (!v) return std::nullopt;
  if (!v->is_boolean()) Fail(key, "must be true or false");
  return v->get<bool>();
}

std::optional<std::string> JsonFields::String(const std::string& key, std::size_t max_length) {
  const nlohmann::json* v = Find(key);
  if (!v) return std::nullopt;
  if (!v->is_string()) Fail(key, "must be a string");
  std::string s = v->get<std::string>();
  if (s.size() > max_length) Fail(key, "is longer than " + std::to_string(max_length) + " bytes");
  return s;
}

const nlohmann::json* JsonFields::Object(const std::string& key) {
  const nlohmann::json* v = Find(key);
  if (v && !v->is_object()) Fail(key, "must be an object");
  return v;
}

const nlohmann::json* JsonFields::Array(const std::string& key) {
  const nlohmann::json* v = Find(key);
  if (v && !v->is_array()) Fail(key, "must be an array");
  return v;
}

double JsonFields::RequiredNumber(const std::string& key) {
  auto v = Number(key);
  if (!v) Fail(key, "is required");
  return *v;
}

std::int64_t JsonFields::RequiredInteger(const std::string& key) {
  auto v = Integer(key);
  if (!v) Fail(key, "is required");
  return *v;
}

std::string JsonFields::RequiredString(const std::string& key, std::size_t max_length) {
  auto v = String(key, max_length);
  if (!v) Fail(key, "is required");
  return *v;
}

void JsonFields::RejectUnknown() const {
  for (const auto& [key, value] : object_.items()) {
    if (!used_.count(key)) throw ApiError::BadRequest(where_ + "." + key + " is not a known field");
  }
}

}  // namespace pslam::server
