#include "api/router.hpp"

#include <nlohmann/json.hpp>

#include <iostream>

#include "service/api_error.hpp"

namespace pslam::server {

ApiResponse JsonResponse(int status, const std::string& json_text) { return {status, "application/json", json_text, {}}; }

ApiResponse ErrorResponse(int status, const std::string& code, const std::string& message) {
  const nlohmann::json body = {{"error", {{"status", status}, {"code", code}, {"message", message}}}};
  return JsonResponse(status, body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

std::vector<std::string> Router::Split(const std::string& path) {
  std::vector<std::string> out;
  std::size_t start = 1;  // paths begin with '/'
  while (start <= path.size()) {
    const std::size_t end = path.find('/', start);
    out.push_back(path.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

void Router::Add(const std::string& method, const std::string& pattern, Access required, Handler handler) {
  routes_.push_back({method, Split(pattern), required, std::move(handler)});
}

ApiResponse Router::Handle(ApiRequest request) const {
  const std::vector<std::string> segments = Split(request.path);
  bool path_known = false;
  for (const Route& route : routes_) {
    if (route.segments.size() != segments.size()) continue;
    std::map<std::string, std::string> params;
    bool match = true;
    for (std::size_t i = 0; i < segments.size() && match; ++i) {
      const std::string& want = route.segments[i];
      if (want.size() > 2 && want.front() == '{' && want.back() == '}') {
        if (segments[i].empty()) match = false;
        params[want.substr(1, want.size() - 2)] = segments[i];
      } else {
        match = want == segments[i];
      }
    }
    if (!match) continue;
    path_known = true;
    const bool head_as_get = request.method == "HEAD" && route.method == "GET";
    if (route.method != request.method && !head_as_get) continue;
    if (request.access < route.required) {
      const int status = request.access == Access::kNone ? 401 : 403;
      if (refusal_log_) refusal_log_(request, status);
      if (status == 401) {
        ApiResponse r = ErrorResponse(401, "unauthorized",
                                      request.token_given ? "the token is not valid" : "a token is required");
        r.headers.emplace_back("WWW-Authenticate", "Bearer");
        return r;
      }
      return ErrorResponse(403, "forbidden", "this token may not do that (read-only token on a write endpoint?)");
    }
    request.params = std::move(params);
    try {
      return route.handler(request);
    } catch (const ApiError& e) {
      ApiResponse r = ErrorResponse(e.status(), e.code(), e.what());
      if (!e.address().empty()) r.headers.emplace_back("Location", "http://" + e.address() + request.target);
      return r;
    } catch (const nlohmann::json::exception& e) {
      return ErrorResponse(400, "bad_request", std::string("invalid JSON: ") + e.what());
    } catch (const std::exception& e) {
      std::cerr << request.method << " " << request.path << ": " << e.what() << "\n";
      return ErrorResponse(500, "internal", "internal error (see the server log)");
    }
  }
  if (path_known) return ErrorResponse(405, "method_not_allowed", request.method + " is not allowed on " + request.path);
  return ErrorResponse(404, "not_found", "no endpoint " + request.path);
}

}  // namespace pslam::server
