#include "link/server_link.hpp"

#include <algorithm>
#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <mutex>
#include <thread>

#include "common/clock.hpp"
#include "common/log.hpp"
#include "link/session_state.hpp"

namespace pslam::agent {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

std::chrono::steady_clock::duration Seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}

// One connection attempt. Handlers hold it by shared_ptr and ignore themselves once it is no
// longer the current one, so a late callback from a dead socket can never touch a new session.
struct Connection {
  explicit Connection(net::io_context& ioc) : ws(ioc) {}
  websocket::stream<beast::tcp_stream> ws;
  beast::flat_buffer read_buffer;
  websocket::response_type handshake_response;
  std::string out_text;
  std::vector<std::uint8_t> out_binary;
  bool writing = false;
  bool welcomed = false;
  bool refusal_reported = false;  // the server said why it turns us away; the close needs no more words
};

}  // namespace

class ServerLink::Impl {
 public:
  Impl(ServerLinkOptions options, Spool& spool, HelloMessage hello)
      : options_(std::move(options)), spool_(spool), hello_(std::move(hello)), resolver_(ioc_), timer_(ioc_) {
    backoff_s_ = options_.backoff_initial_s;
    servers_.push_back(options_.host + ":" + options_.port);
    for (const auto& other : options_.other_servers) {
      if (other.rfind(':') != std::string::npos) servers_.push_back(other);
    }
    if (!options_.session_file.empty()) {
      if (const auto state = LoadSessionState(options_.session_file)) {
        session_id_ = state->session_id;
        seq_base_ = state->seq_base;
        PSLAM_LOG(kInfo) << "will resume server session " << session_id_;
      }
    }
  }

  void Start() {
    net::post(ioc_, [this] { Connect(); });
    thread_ = std::thread([this] { ioc_.run(); });
  }

  void Stop() {
    if (!thread_.joinable()) return;
    net::post(ioc_, [this] {
      stopping_ = true;
      timer_.cancel();
      if (current_) {
        beast::error_code ignored;
        beast::get_lowest_layer(current_->ws).socket().close(ignored);
        current_.reset();
      }
    });
    work_.reset();
    // Give the posted close a moment, then stop whatever is still pending.
    for (int i = 0; i < 50 && !ioc_.stopped(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ioc_.stop();
    thread_.join();
  }

  void Notify() {
    net::post(ioc_, [this] {
      if (current_) Pump(current_);
    });
  }

  LinkStatus status() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    LinkStatus s = status_;
    s.last_server_message_time = last_contact_.load();
    return s;
  }

  std::optional<TargetMessage> TakeTarget() {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto t = std::move(target_);
    target_.reset();
    return t;
  }

  std::optional<std::string> refusal() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return refusal_;
  }

  std::optional<RefusalKind> refusal_kind() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return refusal_kind_;
  }

 private:
  using ConnectionPtr = std::shared_ptr<Connection>;

  void SetState(LinkState state) {
    const std::lock_guard<std::mutex> lock(mutex_);
    status_.state = state;
  }

  void Connect() {
    if (stopping_) return;
    auto conn = std::make_shared<Connection>(ioc_);
    current_ = conn;
    SetState(LinkState::kConnecting);
    resolver_.async_resolve(options_.host, options_.port, [this, conn](beast::error_code ec, tcp::resolver::results_type results) {
      if (conn != current_) return;
      if (ec) return Fail(conn, "resolve " + options_.host, ec);
      beast::get_lowest_layer(conn->ws).expires_after(Seconds(options_.connect_timeout_s));
      beast::get_lowest_layer(conn->ws).async_connect(results, [this, conn](beast::error_code ec, const tcp::endpoint&) {
        if (conn != current_) return;
        if (ec) return Fail(conn, "connect", ec);
        OnConnected(conn);
      });
    });
  }

  void OnConnected(const ConnectionPtr& conn) {
    beast::get_lowest_layer(conn->ws).expires_never();  // the websocket timeouts take over
    websocket::stream_base::timeout timeouts{};
    timeouts.handshake_timeout = Seconds(options_.connect_timeout_s);
    timeouts.idle_timeout = Seconds(options_.idle_timeout_s);
    timeouts.keep_alive_pings = true;
    conn->ws.set_option(timeouts);
    const std::string token = options_.token;
    conn->ws.set_option(websocket::stream_base::decorator([token](websocket::request_type& request) {
      request.set(http::field::user_agent, "pslam-agent");
      if (!token.empty()) request.set(http::field::authorization, "Bearer " + token);
    }));
    conn->ws.control_callback([this](websocket::frame_type, beast::string_view) { last_contact_ = AgentClock::Now(); });
    conn->ws.read_message_max(1 << 20);
    const std::string host = options_.host + ":" + options_.port;
    conn->ws.async_handshake(conn->handshake_response, host, options_.path, [this, conn](beast::error_code ec) {
      if (conn != current_) return;
      if (ec == websocket::error::upgrade_declined) {
        const unsigned status = conn->handshake_response.result_int();
        if (status == 401 || status == 403) {
          return Refuse(conn, RefusalKind::kToken,
                        "the server at " + options_.host + ":" + options_.port + " refused the agent token (HTTP " +
                            std::to_string(status) + "); check --token / PSLAM_AGENT_TOKEN");
        }
        return Fail(conn, "websocket upgrade declined with HTTP " + std::to_string(status), ec);
      }
      if (ec) return Fail(conn, "websocket handshake", ec);
      last_contact_ = AgentClock::Now();
      HelloMessage hello = hello_;
      hello.session = session_id_.empty() ? "new" : session_id_;
      conn->out_text = EncodeHello(hello);
      conn->ws.text(true);
      conn->writing = true;
      conn->ws.async_write(net::buffer(conn->out_text), [this, conn](beast::error_code ec, std::size_t) {
        conn->writing = false;
        if (conn != current_) return;
        if (ec) return Fail(conn, "send hello", ec);
        Pump(conn);
      });
      Read(conn);
    });
  }

  void Read(const ConnectionPtr& conn) {
    conn->ws.async_read(conn->read_buffer, [this, conn](beast::error_code ec, std::size_t) {
      if (conn != current_) return;
      if (ec == websocket::error::closed) {
        const auto reason = conn->ws.reason();
        if (reason.code == websocket::close_code::policy_error) {  // 1008: unauthorized
          return Refuse(conn, RefusalKind::kToken,
                        "the server closed the link with 1008 (policy: " + std::string(reason.reason.c_str()) +
                            "); the agent token was refused; check --token / PSLAM_AGENT_TOKEN");
        }
        const std::string why = std::to_string(reason.code) + " " + std::string(reason.reason.c_str());
        if (reason.code == websocket::close_code::try_again_later && !conn->refusal_reported) {
          ReportRefusal("server refused: " + std::string(reason.reason.c_str()) + " (1013 try again later)");
        }
        return Fail(conn, "server closed the link (" + why + ")", ec);
      }
      if (ec) return Fail(conn, "read", ec);
      last_contact_ = AgentClock::Now();
      const bool text = conn->ws.got_text();
      const std::string message = beast::buffers_to_string(conn->read_buffer.data());
      conn->read_buffer.consume(conn->read_buffer.size());
      if (text) Handle(conn, ParseServerMessage(message));
      if (conn == current_) Read(conn);
    });
  }

  void Handle(const ConnectionPtr& conn, const ServerMessage& message) {
    if (const auto* ack = std::get_if<AckMessage>(&message)) {
      // The status first: whoever sees the spool drop the records then sees the ack reported.
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        status_.acked_wire_seq = std::max(status_.acked_wire_seq, ack->seq);
      }
      spool_.Acknowledge(ack->seq + seq_base_);
      paused_ = false;
      return Pump(conn);
    }
    if (const auto* welcome = std::get_if<WelcomeMessage>(&message)) return OnWelcome(conn, *welcome);
    if (const auto* target = std::get_if<TargetMessage>(&message)) {
      const std::lock_guard<std::mutex> lock(mutex_);
      target_ = *target;
      return;
    }
    if (const auto* error = std::get_if<ErrorMessage>(&message)) return OnServerError(conn, *error);
    if (const auto* redirect = std::get_if<RedirectMessage>(&message)) return OnRedirect(conn, *redirect);
    PSLAM_LOG(kWarning) << std::get<UnknownMessage>(message).description;
  }

  void OnRedirect(const ConnectionPtr& conn, const RedirectMessage& redirect) {
    const auto colon = redirect.address.rfind(':');
    if (conn->welcomed || colon == std::string::npos || colon == 0 || colon + 1 == redirect.address.size()) {
      PSLAM_LOG(kWarning) << "ignoring a redirect to '" << redirect.address << "'";
      return;
    }
    PSLAM_LOG(kInfo) << "redirected from " << options_.host << ":" << options_.port << " to " << redirect.address;
    if (std::find(servers_.begin(), servers_.end(), redirect.address) == servers_.end()) {
      servers_.push_back(redirect.address);
    }
    UseServer(redirect.address);
    conn->refusal_reported = true;
    // Straight to the node named, once; a chain of redirects backs off like any failure.
    hello_.redirected = true;
    if (++redirects_ <= 2) backoff_s_ = 0.0;
    Fail(conn, "redirected to " + redirect.address, {});
  }

  void UseServer(const std::string& address) {
    const auto colon = address.rfind(':');
    options_.host = address.substr(0, colon);
    options_.port = address.substr(colon + 1);
    current_server_ = static_cast<std::size_t>(std::find(servers_.begin(), servers_.end(), address) - servers_.begin());
  }

  void OnWelcome(const ConnectionPtr& conn, const WelcomeMessage& welcome) {
    if (welcome.session_id != session_id_) {
      // A new session (or the server could not resume ours): its seq 1 is our first unacked record.
      if (!session_id_.empty()) {
        PSLAM_LOG(kWarning) << "server opened session " << welcome.session_id << " instead of resuming " << session_id_;
      }
      session_id_ = welcome.session_id;
      seq_base_ = spool_.acked_seq();
      if (!options_.session_file.empty()) SaveSessionState(options_.session_file, {session_id_, seq_base_});
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);  // before the spool, as for an ack
      status_.state = LinkState::kStreaming;
      status_.session_id = session_id_;
      status_.acked_wire_seq = welcome.last_acked_seq;
      ++status_.connections;
    }
    spool_.Acknowledge(welcome.last_acked_seq + seq_base_);
    next_send_ = spool_.acked_seq() + 1;
    paused_ = false;
    conn->welcomed = true;
    hello_.redirected = false;
    redirects_ = 0;
    last_refusal_.clear();
    backoff_s_ = options_.backoff_initial_s;
    const std::uint64_t backlog = spool_.next_seq() - next_send_;
    PSLAM_LOG(kInfo) << "streaming to " << options_.host << ":" << options_.port << " in session " << session_id_
                     << " from seq " << next_send_ - seq_base_ << " (" << backlog << " message(s) waiting)";
    Pump(conn);
  }

  void OnServerError(const ConnectionPtr& conn, const ErrorMessage& error) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      ++status_.server_errors;
    }
    if (error.code == "unauthorized") {
      return Refuse(conn, RefusalKind::kToken,
                    "the server refused the agent token (" + error.message + "); check --token / PSLAM_AGENT_TOKEN");
    }
    if (error.code == "bad_message" && !conn->welcomed) {
      // The answer to our hello: the same hello would be refused again.
      return Refuse(conn, RefusalKind::kSession,
                    "server refused the hello: " + error.message + " (bad_message); check the agent's options");
    }
    if (error.code == "engine_failed") {
      return Refuse(conn, RefusalKind::kSession,
                    "server session " + session_id_ + " failed: " + error.message +
                        " (engine_failed); its events say why; not resending into it");
    }
    if (!conn->welcomed && (error.code == "overloaded" || error.code == "storage_error" ||
                            error.code == "hello_timeout" || error.code == "session_moving")) {
      // Turned away for now: the server closes the link next and we retry.
      conn->refusal_reported = true;
      return ReportRefusal("server refused: " + error.message + " (" + error.code + "); retrying");
    }
    if (error.code == "unknown_session") {
      PSLAM_LOG(kWarning) << "server does not know session " << session_id_ << " (" << error.message
                          << "); starting a new one";
      session_id_.clear();
      if (!options_.session_file.empty()) ClearSessionState(options_.session_file);
      backoff_s_ = 0.0;  // reconnect at once with "new"
      return Fail(conn, "unknown session", {});
    }
    if (error.code == "overloaded") {
      paused_ = true;  // wait for the next ack before sending more
      return;
    }
    PSLAM_LOG(kWarning) << "server error " << error.code << ": " << error.message;
  }

  void Pump(const ConnectionPtr& conn) {
    if (conn != current_ || !conn->welcomed || conn->writing || paused_ || stopping_) return;
    const std::uint64_t acked = spool_.acked_seq();
    if (next_send_ <= acked) next_send_ = acked + 1;
    if (next_send_ - acked - 1 >= options_.max_in_flight) return;  // window full: wait for acks
    std::optional<SpoolRecord> record;
    try {
      record = spool_.Read(next_send_);
    } catch (const std::exception& e) {
      PSLAM_LOG(kError) << e.what();
      return Fail(conn, "spool read", {});
    }
    if (!record) return;
    const std::uint64_t wire_seq = record->seq - seq_base_;
    bool binary = false;
    if (options_.binary_scans && IsScanRecord(record->payload)) {
      conn->out_binary = *ScanRecordToBinary(record->payload, wire_seq);
      binary = true;
    } else if (const auto message = DecodeRecord(record->payload)) {
      conn->out_text = std::holds_alternative<OdomMessage>(*message)
                           ? EncodeOdomJson(std::get<OdomMessage>(*message), wire_seq)
                           : EncodeScanJson(std::get<ScanMessage>(*message), wire_seq);
    } else {
      // Cannot happen with a CRC-checked record written by us; skip rather than wedge the link.
      PSLAM_LOG(kError) << "spool record " << record->seq << " is not an agent message; skipped";
      ++next_send_;
      return Pump(conn);
    }
    conn->writing = true;
    conn->ws.binary(binary);
    auto on_written = [this, conn](beast::error_code ec, std::size_t) {
      conn->writing = false;
      if (conn != current_) return;
      if (ec) return Fail(conn, "write", ec);
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        ++status_.sent;
        if (next_send_ <= highest_sent_) ++status_.resent;
      }
      highest_sent_ = std::max(highest_sent_, next_send_);
      ++next_send_;
      Pump(conn);
    };
    if (binary) {
      conn->ws.async_write(net::buffer(conn->out_binary), on_written);
    } else {
      conn->ws.async_write(net::buffer(conn->out_text), on_written);
    }
  }

  void Drop(const ConnectionPtr& conn) {
    beast::error_code ignored;
    beast::get_lowest_layer(conn->ws).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(conn->ws).socket().close(ignored);
    current_.reset();
  }

  void Fail(const ConnectionPtr& conn, const std::string& what, beast::error_code ec) {
    if (conn != current_) return;
    const bool was_streaming = conn->welcomed;
    Drop(conn);
    const std::string text = ec ? what + ": " + ec.message() : what;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      status_.state = LinkState::kDisconnected;
      status_.last_error = text;
      ++status_.failures;
    }
    if (was_streaming) {
      PSLAM_LOG(kWarning) << "link to " << options_.host << ":" << options_.port << " lost (" << text
                          << "); reconnecting, unacknowledged messages stay spooled";
    } else {
      PSLAM_LOG(kDebug) << "cannot reach " << options_.host << ":" << options_.port << " (" << text << "); retry in "
                        << backoff_s_ << " s";
    }
    if (stopping_) return;
    // A node that cannot be reached: the next one of the fleet, if we know others.
    if (!was_streaming && !conn->refusal_reported && servers_.size() > 1) {
      current_server_ = (current_server_ + 1) % servers_.size();
      UseServer(servers_[current_server_]);
    }
    timer_.expires_after(Seconds(backoff_s_));
    timer_.async_wait([this](beast::error_code ec) {
      if (!ec) Connect();
    });
    backoff_s_ = std::clamp(backoff_s_ * 2.0, options_.backoff_initial_s, options_.backoff_max_s);
  }

  void Refuse(const ConnectionPtr& conn, RefusalKind kind, const std::string& message) {
    Drop(conn);
    PSLAM_LOG(kError) << message;
    const std::lock_guard<std::mutex> lock(mutex_);
    status_.state = LinkState::kRefused;
    status_.last_error = message;
    refusal_ = message;
    refusal_kind_ = kind;
  }

  // A transient refusal, at normal verbosity; repeats of the same words only with --verbose.
  void ReportRefusal(const std::string& message) {
    if (message == last_refusal_) {
      PSLAM_LOG(kDebug) << message;
    } else {
      PSLAM_LOG(kWarning) << message;
      last_refusal_ = message;
    }
  }

  ServerLinkOptions options_;
  Spool& spool_;
  HelloMessage hello_;
  net::io_context ioc_;
  net::executor_work_guard<net::io_context::executor_type> work_ = net::make_work_guard(ioc_);
  tcp::resolver resolver_;
  net::steady_timer timer_;
  std::thread thread_;

  // Owned by the io thread.
  ConnectionPtr current_;
  std::string session_id_;
  std::uint64_t seq_base_ = 0;
  std::uint64_t next_send_ = 1;     // spool seq of the next record to write
  std::uint64_t highest_sent_ = 0;  // to tell resends from first sends
  double backoff_s_ = 0.0;
  bool paused_ = false;
  bool stopping_ = false;
  std::string last_refusal_;
  std::vector<std::string> servers_;  // HOST:PORT of every node we know, the first given first
  std::size_t current_server_ = 0;
  int redirects_ = 0;                  // since the last welcome

  std::atomic<double> last_contact_{0.0};
  mutable std::mutex mutex_;  // guards status_, target_, refusal_
  LinkStatus status_;
  std::optional<TargetMessage> target_;
  std::optional<std::string> refusal_;
  std::optional<RefusalKind> refusal_kind_;
};

ServerLink::ServerLink(ServerLinkOptions options, Spool& spool, HelloMessage hello)
    : impl_(std::make_unique<Impl>(std::move(options), spool, std::move(hello))) {}
ServerLink::~ServerLink() { Stop(); }
void ServerLink::Start() { impl_->Start(); }
void ServerLink::Stop() { impl_->Stop(); }
void ServerLink::Notify() { impl_->Notify(); }
LinkStatus ServerLink::status() const { return impl_->status(); }
std::optional<TargetMessage> ServerLink::TakeTarget() { return impl_->TakeTarget(); }
std::optional<std::string> ServerLink::refusal() const { return impl_->refusal(); }
std::optional<RefusalKind> ServerLink::refusal_kind() const { return impl_->refusal_kind(); }

}  // namespace pslam::agent
