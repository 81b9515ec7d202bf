#pragma once
// Method + path pattern -> handler, and the one place where failures become HTTP statuses:
// ApiError carries its own, a JSON error is 400, a missing route 404 (405 for a known path with
// another method), insufficient access 401/403, anything else 500 with a generic body (details go
// to the log, not to the client).
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "api/access.hpp"

namespace pslam::server {

struct ApiRequest {
  std::string method;                          // "GET", "POST", ...
  std::string path;                            // decoded, without the query
  std::string target;                          // as received, with the query (for redirects)
  std::map<std::string, std::string> query;    // decoded
  std::string body;
  Access access = Access::kNone;
  bool token_given = false;
  std::map<std::string, std::string> params;   // from {name} segments of the route
  std::string remote;                          // for the log

  const std::string& Param(const std::string& name) const { return params.at(name); }
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

ApiResponse JsonResponse(int status, const std::string& json_text);
ApiResponse ErrorResponse(int status, const std::string& code, const std::string& message);

class Router {
 public:
  using Handler = std::function<ApiResponse(const ApiRequest&)>;
  // Called for refused requests (401/403), to log them.
  using RefusalLog = std::function<void(const ApiRequest&, int status)>;

  // 'pattern' is a path whose segments are literals or {name} (one whole segment).
  void Add(const std::string& method, const std::string& pattern, Access required, Handler handler);
  void SetRefusalLog(RefusalLog log) { refusal_log_ = std::move(log); }
  ApiResponse Handle(ApiRequest request) const;

 private:
  struct Route {
    std::string method;
    std::vector<std::string> segments;
    Access required;
    Handler handler;
  };
  static std::vector<std::string> Split(const std::string& path);

  std::vector<Route> routes_;
  RefusalLog refusal_log_;
};

}  // namespace pslam::server
