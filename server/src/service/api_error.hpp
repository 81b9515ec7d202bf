#pragma once
// An error a request can cause, with the HTTP status it maps to. Services throw it; the router is
// the one place that turns it (and any other exception) into a response.
#include <stdexcept>
#include <string>

namespace pslam::server {

class ApiError : public std::runtime_error {
 public:
  ApiError(int status, std::string code, const std::string& message)
      : std::runtime_error(message), status_(status), code_(std::move(code)) {}
  int status() const { return status_; }
  const std::string& code() const { return code_; }

  static ApiError BadRequest(const std::string& message) { return {400, "bad_request", message}; }
  static ApiError NotFound(const std::string& message) { return {404, "not_found", message}; }
  static ApiError Conflict(const std::string& message) { return {409, "conflict", message}; }
  static ApiError Forbidden(const std::string& message) { return {403, "forbidden", message}; }
  static ApiError Unavailable(const std::string& message) { return {503, "unavailable", message}; }
  // Another node of the fleet runs the session: the same request goes to 'address' (HOST:PORT).
  static ApiError Elsewhere(const std::string& address, const std::string& message) {
    ApiError e(307, "elsewhere", message);
    e.address_ = address;
    return e;
  }
  const std::string& address() const { return address_; }

 private:
  int status_;
  std::string code_;
  std::string address_;
};

}  // namespace pslam::server
