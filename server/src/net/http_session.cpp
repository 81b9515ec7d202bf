#include "net/http_session.hpp"

#include "api/query.hpp"
#include "net/foxglove_session.hpp"
#include "net/ingest_session.hpp"
#include "net/live_session.hpp"

namespace pslam::server {
namespace {

// RFC 9112 6.3: a request whose final transfer coding is not "chunked" has no determinable length
// (400, then close); 6.1: chunked after a coding we do not decode (gzip, ...) is 501. Beast reads
// such a request as one without a body, so the check is ours. Returns the refusal, if any.
std::optional<ApiResponse> CheckTransferCoding(const http::request<http::string_body>& req) {
  const auto fields = req.equal_range(http::field::transfer_encoding);
  if (fields.first == fields.second) return std::nullopt;
  std::vector<std::string> codings;  // several fields are one list, in order
  for (auto field = fields.first; field != fields.second; ++field) {
    for (const auto& coding : http::token_list(field->value())) codings.emplace_back(coding);
  }
  if (codings.empty() || !beast::iequals(codings.back(), "chunked")) {
    return ErrorResponse(400, "bad_request", "the final transfer coding must be chunked (RFC 9112 6.3)");
  }
  if (codings.size() > 1) return ErrorResponse(501, "not_implemented", "only the chunked transfer coding is supported");
  return std::nullopt;
}

}  // namespace

HttpSession::HttpSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context)
    : stream_(std::move(socket)), context_(std::move(context)) {
  beast::error_code ec;
  const auto endpoint = stream_.socket().remote_endpoint(ec);
  remote_ = ec ? "?" : endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
}

void HttpSession::Run() {
  net::dispatch(stream_.get_executor(), beast::bind_front_handler(&HttpSession::Read, shared_from_this()));
}

void HttpSession::Read() {
  parser_.emplace();
  parser_->body_limit(context_->limits.max_body_bytes);
  stream_.expires_after(context_->limits.http_timeout);
  http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::OnRead, shared_from_this()));
}

void HttpSession::OnRead(beast::error_code ec, std::size_t) {
  if (ec == http::error::end_of_stream) return Close();
  if (ec == http::error::body_limit) {
    return Respond(ToBeastResponse(
        ErrorResponse(413, "too_large", "the body exceeds " + std::to_string(context_->limits.max_body_bytes) + " bytes"),
        11, false, false));
  }
  if (ec == beast::error::timeout || ec == net::error::operation_aborted || ec == net::error::eof ||
      ec == net::error::connection_reset) {
    return Fail(ec, "http read");
  }
  if (ec) {
    // A malformed request: say so, then close (the stream cannot be resynchronised).
    return Respond(ToBeastResponse(ErrorResponse(400, "bad_request", "malformed HTTP request: " + ec.message()), 11,
                                   false, false));
  }
  if (auto refusal = CheckTransferCoding(parser_->get())) {
    return Respond(ToBeastResponse(std::move(*refusal), parser_->get().version(), false, false));
  }
  http::request<http::string_body> req = parser_->release();
  if (websocket::is_upgrade(req)) return Upgrade(std::move(req));
  // The handler may block on storage or render a map: never on this network thread.
  net::post(context_->workers, [self = shared_from_this(), req = std::move(req)]() mutable {
    auto res = self->context_->HandleHttp(req, self->remote_);
    net::post(self->stream_.get_executor(), [self, res = std::move(res)]() mutable { self->Respond(std::move(res)); });
  });
}

void HttpSession::Upgrade(http::request<http::string_body> req) {
  stream_.expires_never();  // the WebSocket sets its own timeouts
  const auto target = ParseTarget(std::string_view(req.target().data(), req.target().size()));
  const std::string path = target ? target->path : "";
  bool token_given = false;
  const Access access = context_->AccessOf(req, &token_given);
  if (path == "/api/ingest") {
    // The ingest protocol reports a refused token inside the WebSocket (error, then close 1008).
    std::make_shared<IngestSession>(stream_.release_socket(), context_, access, remote_, ServerContext::TokenOf(req))
        ->Run(std::move(req));
    return;
  }
  // Viewer sockets need a viewer (read) or agent token.
  const auto refuse_unauthorized = [&] {
    context_->LogRefusal("GET", path, remote_, 401);
    ApiResponse r = ErrorResponse(401, "unauthorized", token_given ? "the token is not valid" : "a token is required");
    r.headers.emplace_back("WWW-Authenticate", "Bearer");
    Respond(ToBeastResponse(std::move(r), req.version(), false, false));
  };
  constexpr std::string_view kPrefix = "/api/sessions/", kSuffix = "/live";
  if (path.size() > kPrefix.size() + kSuffix.size() && path.rfind(kPrefix, 0) == 0 &&
      path.compare(path.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0) {
    const std::string id = path.substr(kPrefix.size(), path.size() - kPrefix.size() - kSuffix.size());
    if (access < Access::kRead) return refuse_unauthorized();
    std::make_shared<LiveSession>(stream_.release_socket(), context_, id, ServerContext::TokenOf(req))->Run(std::move(req));
    return;
  }
  if (path == "/foxglove") {
    if (access < Access::kRead) return refuse_unauthorized();
    const auto subprotocol = ChooseFoxgloveSubprotocol(req);
    if (!subprotocol) {
      return Respond(ToBeastResponse(
          ErrorResponse(400, "bad_request", "offer the subprotocol foxglove.sdk.v1 or foxglove.websocket.v1"),
          req.version(), false, false));
    }
    std::make_shared<FoxgloveSession>(stream_.release_socket(), context_, ServerContext::TokenOf(req), *subprotocol)
        ->Run(std::move(req));
    return;
  }
  Respond(ToBeastResponse(ErrorResponse(404, "not_found", "no WebSocket endpoint " + path), req.version(), false, false));
}

void HttpSession::Respond(http::response<http::string_body> res) {
  const bool keep_alive = res.keep_alive();
  response_ = std::make_shared<http::response<http::string_body>>(std::move(res));
  stream_.expires_after(context_->limits.http_timeout);
  http::async_write(stream_, *response_,
                    beast::bind_front_handler(&HttpSession::OnWrite, shared_from_this(), keep_alive));
}

void HttpSession::OnWrite(bool keep_alive, beast::error_code ec, std::size_t) {
  if (ec) return Fail(ec, "http write");
  response_.reset();
  if (!keep_alive) return Close();
  Read();
}

void HttpSession::Close() {
  beast::error_code ec;
  stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  // Lingering close: a client may still be sending a body we refused. Closing now, with its bytes
  // unread, would reset the connection and could destroy the answer before the client reads it;
  // read and discard until the client closes too, for a bounded time.
  stream_.expires_after(std::chrono::seconds(2));
  Drain();
}

void HttpSession::Drain() {
  drain_buffer_.resize(16384);
  stream_.async_read_some(net::buffer(drain_buffer_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (!ec) self->Drain();
  });
}

}  // namespace pslam::server
