#include "net/server_context.hpp"

#include <algorithm>
#include <iostream>

#include "api/query.hpp"

namespace pslam::server {

Access ServerContext::AccessOf(const http::request<http::string_body>& req, bool* token_given) const {
  const std::string token = TokenOf(req);
  *token_given = !token.empty();
  return auth.Check(token);
}

std::string ServerContext::TokenOf(const http::request<http::string_body>& req) {
  std::string token;
  const auto auth_header = req.find(http::field::authorization);
  if (auth_header != req.end()) {
    const beast::string_view value = auth_header->value();
    constexpr beast::string_view kBearer = "Bearer ";
    if (value.size() > kBearer.size() && beast::iequals(value.substr(0, kBearer.size()), kBearer)) {
      token = std::string(value.substr(kBearer.size()));
    } else {
      token.assign(1, '\x01');  // a malformed header is a wrong token, not a missing one
    }
  } else if (const auto target = ParseTarget(std::string_view(req.target().data(), req.target().size()))) {
    const auto it = target->query.find("token");
    if (it != target->query.end()) token = it->second;
  }
  return token;
}

void ServerContext::LogRefusal(const std::string& method, const std::string& path, const std::string& remote,
                               int status) {
  std::cerr << "refused " << method << " " << path.substr(0, 200) << " from " << remote << ": " << status << "\n";
  mapping.LogEvent(std::nullopt, "refused",
                   {{"method", method}, {"path", path.substr(0, 200)}, {"remote", remote}, {"status", status}});
}

http::response<http::string_body> ToBeastResponse(ApiResponse r, unsigned version, bool keep_alive, bool head) {
  http::response<http::string_body> res{static_cast<http::status>(r.status), version};
  res.set(http::field::server, "pslam-server");
  res.set(http::field::content_type, r.content_type);
  bool cache_set = false;
  for (const auto& [name, value] : r.headers) {
    res.set(name, value);
    cache_set = cache_set || beast::iequals(name, "Cache-Control");
  }
  if (!cache_set) res.set(http::field::cache_control, "no-store");  // API answers describe a moving state
  res.keep_alive(keep_alive);
  const std::size_t size = r.body.size();
  if (!head) res.body() = std::move(r.body);
  res.content_length(size);
  return res;
}

http::response<http::string_body> ServerContext::HandleHttp(const http::request<http::string_body>& req,
                                                            const std::string& remote) {
  const std::string method(req.method_string());
  const bool head = req.method() == http::verb::head;
  const auto target = ParseTarget(std::string_view(req.target().data(), req.target().size()));
  if (!target) {
    return ToBeastResponse(ErrorResponse(400, "bad_request", "malformed request target"), req.version(),
                           req.keep_alive(), head);
  }
  if (target->path.rfind("/api/", 0) == 0 || target->path == "/api") {
    ApiRequest api;
    api.method = method;
    api.path = target->path;
    api.target = std::string(req.target());
    api.query = target->query;
    api.body = req.body();
    api.remote = remote;
    api.access = AccessOf(req, &api.token_given);
    return ToBeastResponse(router.Handle(std::move(api)), req.version(), req.keep_alive(), head);
  }
  if (req.method() != http::verb::get && !head) {
    return ToBeastResponse(ErrorResponse(405, "method_not_allowed", "static files are GET only"), req.version(),
                           req.keep_alive(), head);
  }
  const auto etag = req.find(http::field::if_none_match);
  return ToBeastResponse(files.Serve(target->path, etag == req.end() ? "" : std::string(etag->value())), req.version(),
                         req.keep_alive(), head);
}

std::optional<std::string> ServerContext::Track(const std::shared_ptr<Closable>& socket, SocketKind kind,
                                                const std::string& token) {
  std::vector<std::shared_ptr<Closable>> evicted;
  std::optional<std::string> refusal;
  {
    std::lock_guard lock(mutex_);
    sockets_.erase(std::remove_if(sockets_.begin(), sockets_.end(), [](const auto& t) { return t.socket.expired(); }),
                   sockets_.end());
    // Room in the quota of 'in_scope' sockets, made by evicting its oldest silent one if need be.
    auto make_room = [&](auto in_scope, std::size_t limit) {
      if (static_cast<std::size_t>(std::count_if(sockets_.begin(), sockets_.end(), in_scope)) < limit) return true;
      for (auto it = sockets_.begin(); it != sockets_.end(); ++it) {
        auto s = it->socket.lock();
        if (s && in_scope(*it) && s->Silent()) {
          evicted.push_back(std::move(s));
          sockets_.erase(it);
          return true;
        }
      }
      return false;
    };
    const bool agent = kind == SocketKind::kAgent;
    if (!make_room([&](const Tracked& t) { return t.kind == kind; },
                   agent ? limits.max_agent_websockets : limits.max_viewer_websockets)) {
      refusal = agent ? "too many agent connections" : "too many viewer connections";
    } else if (!token.empty() &&
               !make_room([&](const Tracked& t) { return t.token == token; }, limits.max_websockets_per_token)) {
      refusal = "too many connections with this token";
    } else {
      sockets_.push_back({socket, kind, token});
    }
  }
  for (const auto& s : evicted) s->CloseSilent();
  return refusal;
}

void ServerContext::CloseAll() {
  std::vector<std::shared_ptr<Closable>> open;
  {
    std::lock_guard lock(mutex_);
    for (const auto& t : sockets_) {
      if (auto s = t.socket.lock()) open.push_back(std::move(s));
    }
    sockets_.clear();
  }
  for (const auto& s : open) s->CloseForShutdown();
}

std::size_t ServerContext::websockets() {
  std::lock_guard lock(mutex_);
  std::size_t n = 0;
  for (const auto& t : sockets_) n += t.socket.expired() ? 0 : 1;
  return n;
}

}  // namespace pslam::server
