#pragma once
// A value or an error message, for factories that must not half-construct (STYLE 6.8: the listener
// and the storage are created through functions returning Result, never "log and run anyway").
#include <string>
#include <utility>
#include <variant>

namespace pslam::server {

struct Error {
  std::string message;
};

template <typename T>
class Result {
 public:
  Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit, like std::expected
  Result(Error error) : value_(std::move(error)) {}  // NOLINT

  bool ok() const { return std::holds_alternative<T>(value_); }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<T>(value_); }
  const T& value() const { return std::get<T>(value_); }
  const std::string& error() const { return std::get<Error>(value_).message; }

 private:
  std::variant<T, Error> value_;
};

}  // namespace pslam::server
