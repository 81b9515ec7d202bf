#pragma once
// Reads a sequence number from JSON: a non-negative integer, else std::invalid_argument.
// nlohmann's get<std::uint64_t>() casts a float or a negative number instead, which is undefined
// for values out of range (a fuzzed welcome carried -7.7e128).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

namespace pslam::agent {

// The field 'name' of object j; 'missing' stands in for an absent field, if given.
inline std::uint64_t SequenceField(const nlohmann::json& j, const char* name,
                                   std::optional<std::uint64_t> missing = std::nullopt) {
  if (missing && !j.contains(name)) return *missing;
  const auto& value = j.at(name);
  if (!value.is_number_unsigned()) throw std::invalid_argument(std::string(name) + " must be a non-negative integer");
  return value.get<std::uint64_t>();
}

}  // namespace pslam::agent
