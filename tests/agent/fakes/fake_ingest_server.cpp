#include "fakes/fake_ingest_server.hpp"

#include <utility>  // before Boost 1.74 asio: its awaitable.hpp uses std::exchange without it

#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace pslam::agent::testing {

class FakeIngestServer::Impl {
 public:
  explicit Impl(FakeIngestOptions options) : options_(std::move(options)) {}
  ~Impl() { Kill(); }

  // Listens on 127.0.0.1:'port' (0: a free port). Returns the port.
  unsigned short Start(unsigned short port = 0) {
    Kill();
    ioc_ = std::make_unique<boost::asio::io_context>();
    acceptor_ = std::make_unique<tcp::acceptor>(*ioc_);
    const tcp::endpoint endpoint(boost::asio::ip::make_address("127.0.0.1"), port);
    acceptor_->open(endpoint.protocol());
    acceptor_->set_option(boost::asio::socket_base::reuse_address(true));
    acceptor_->bind(endpoint);
    acceptor_->listen();
    port_ = acceptor_->local_endpoint().port();
    commit_timer_ = std::make_unique<boost::asio::steady_timer>(*ioc_);
    Accept();
    ScheduleCommit();
    thread_ = std::thread([this] { ioc_->run(); });
    return port_;
  }

  // Abrupt stop: sockets closed without a close frame, uncommitted messages lost.
  void Kill() {
    if (!ioc_) return;
    boost::asio::post(*ioc_, [this] {
      boost::system::error_code ignored;
      acceptor_->close(ignored);
      commit_timer_->cancel();
      for (auto& weak : sessions_) {
        if (auto s = weak.lock()) boost::beast::get_lowest_layer(s->ws).socket().close(ignored);
      }
      ioc_->stop();
    });
    thread_.join();
    sessions_.clear();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      pending_.clear();
    }
    commit_timer_.reset();
    acceptor_.reset();
    ioc_.reset();
  }

  unsigned short port() const { return port_; }
  // A silent server: nothing is committed or acknowledged while off.
  void set_acks_enabled(bool on) { acks_enabled_ = on; }

  void SendToAll(const nlohmann::json& message) {
    if (!ioc_) return;
    boost::asio::post(*ioc_, [this, text = message.dump()] {
      for (auto& weak : sessions_) {
        if (auto s = weak.lock()) Write(s, text);
      }
    });
  }

  std::map<std::string, FakeSession> sessions() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return store_;
  }
  std::size_t welcomes() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return welcomes_;
  }
  std::size_t refused() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return refused_;
  }

 private:
  using tcp = boost::asio::ip::tcp;
  struct Session {
    explicit Session(tcp::socket socket) : ws(std::move(socket)) {}
    boost::beast::websocket::stream<boost::beast::tcp_stream> ws;
    boost::beast::flat_buffer buffer;
    boost::beast::http::request<boost::beast::http::string_body> request;
    std::vector<std::string> out;
    bool writing = false;
    bool authorized = false;
    std::string session_id;
  };
  using SessionPtr = std::shared_ptr<Session>;

  void Accept() {
    acceptor_->async_accept([this](boost::system::error_code ec, tcp::socket socket) {
      if (ec) return;
      auto s = std::make_shared<Session>(std::move(socket));
      sessions_.push_back(s);
      ReadUpgrade(s);
      Accept();
    });
  }

  bool TokenOk(const Session& s) const {
    const auto auth = s.request[boost::beast::http::field::authorization];
    if (std::string(auth) == "Bearer " + options_.token) return true;
    const std::string target(s.request.target());
    return target.find("token=" + options_.token) != std::string::npos;
  }

  void ReadUpgrade(const SessionPtr& s) {
    namespace http = boost::beast::http;
    http::async_read(s->ws.next_layer(), s->buffer, s->request, [this, s](boost::system::error_code ec, std::size_t) {
      if (ec) return;
      s->authorized = TokenOk(*s);
      if (!s->authorized) {
        const std::lock_guard<std::mutex> lock(mutex_);
        ++refused_;
      }
      if (!s->authorized && !options_.refuse_in_band) {
        auto res = std::make_shared<http::response<http::string_body>>(http::status::unauthorized, s->request.version());
        res->set(http::field::content_type, "application/json");
        res->body() = R"({"error":"unauthorized","message":"bad agent token"})";
        res->prepare_payload();
        http::async_write(s->ws.next_layer(), *res, [s, res](boost::system::error_code, std::size_t) {
          boost::system::error_code ignored;
          boost::beast::get_lowest_layer(s->ws).socket().close(ignored);
        });
        return;
      }
      s->ws.async_accept(s->request, [this, s](boost::system::error_code ec) {
        if (ec) return;
        if (!s->authorized) {
          Write(s, R"({"type":"error","code":"unauthorized","message":"bad agent token"})");
          s->ws.async_close({boost::beast::websocket::close_code::policy_error, "unauthorized"},
                            [s](boost::system::error_code) {});
          return;
        }
        Read(s);
      });
    });
  }

  void Read(const SessionPtr& s) {
    s->ws.async_read(s->buffer, [this, s](boost::system::error_code ec, std::size_t) {
      if (ec) return;
      const bool text = s->ws.got_text();
      std::string data = boost::beast::buffers_to_string(s->buffer.data());
      s->buffer.consume(s->buffer.size());
      OnMessage(s, data, text);
      Read(s);
    });
  }

  void OnMessage(const SessionPtr& s, const std::string& data, bool text) {
    if (s->session_id.empty()) return OnHello(s, data);
    StoredMessage m;
    try {
      if (text) {
        const auto j = nlohmann::json::parse(data);
        m.type = j.at("type").get<std::string>();
        m.seq = j.at("seq").get<std::uint64_t>();
        m.t = j.at("t").get<double>();
        if (m.type == "scan") {
          for (const auto& r : j.at("ranges")) {
            if (r.is_null()) ++m.null_ranges;
            else if (!r.is_number()) throw std::runtime_error("ranges must be numbers or null");
          }
          m.ranges = j.at("ranges").size();
          m.x = j.at("odom").at("x").get<double>();
          m.y = j.at("odom").at("y").get<double>();
          m.theta = j.at("odom").at("theta").get<double>();
        } else if (m.type == "odom") {
          for (const char* k : {"x", "y", "theta", "v", "w"}) j.at(k).get<double>();
          m.x = j.at("x").get<double>();
          m.y = j.at("y").get<double>();
          m.theta = j.at("theta").get<double>();
          m.v = j.at("v").get<double>();
        } else {
          throw std::runtime_error("unknown type " + m.type);
        }
      } else {
        if (data.size() < 48 || std::memcmp(data.data(), "PSC1", 4) != 0) throw std::runtime_error("bad binary scan");
        std::uint32_t n = 0;
        std::memcpy(&m.seq, data.data() + 4, 8);
        std::memcpy(&m.t, data.data() + 12, 8);
        std::memcpy(&n, data.data() + 44, 4);
        std::memcpy(&m.x, data.data() + 20, 8);
        std::memcpy(&m.y, data.data() + 28, 8);
        std::memcpy(&m.theta, data.data() + 36, 8);
        if (data.size() != 48 + 4ull * n) throw std::runtime_error("binary scan size does not match n");
        m.type = "scan";
        m.ranges = n;
        m.binary = true;
        for (std::uint32_t i = 0; i < n; ++i) {
          float r;
          std::memcpy(&r, data.data() + 48 + 4 * i, 4);
          if (r != r) ++m.null_ranges;
        }
      }
    } catch (const std::exception& e) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        ++store_[s->session_id].bad_messages;
      }
      Write(s, nlohmann::json{{"type", "error"}, {"code", "bad_message"}, {"message", e.what()}}.dump());
      return;
    }
    std::uint64_t reack = 0;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      FakeSession& session = store_[s->session_id];
      auto& pending = pending_[s->session_id];
      const std::uint64_t last = pending.empty() ? session.last_acked : pending.back().seq;
      if (m.seq <= last) {
        ++session.duplicates;  // already stored (or pending): ignored, acknowledged again
        if (m.seq <= session.last_acked) reack = session.last_acked;
      } else {
        if (m.seq != last + 1) ++session.gaps;
        pending.push_back(m);
      }
    }
    if (reack > 0) Write(s, nlohmann::json{{"type", "ack"}, {"seq", reack}}.dump());
  }

  void OnHello(const SessionPtr& s, const std::string& data) {
    nlohmann::json hello;
    try {
      hello = nlohmann::json::parse(data);
      if (hello.at("type") != "hello" || hello.at("version") != 1) throw std::runtime_error("expected hello v1");
      hello.at("laser").at("beams").get<std::size_t>();
    } catch (const std::exception& e) {
      Write(s, nlohmann::json{{"type", "error"}, {"code", "bad_message"}, {"message", e.what()}}.dump());
      return;
    }
    const std::string requested = hello.value("session", "new");
    std::uint64_t last_acked = 0;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (requested == "new") {
        s->session_id = "s-" + std::to_string(store_.size() + 1);
        store_[s->session_id].hello = hello;
      } else if (store_.count(requested)) {
        s->session_id = requested;
      }
      if (!s->session_id.empty()) {
        last_acked = store_[s->session_id].last_acked;
        ++welcomes_;
      }
    }
    if (s->session_id.empty()) {
      Write(s, nlohmann::json{{"type", "error"}, {"code", "unknown_session"}, {"message", "no session " + requested}}.dump());
      return;
    }
    Write(s, nlohmann::json{{"type", "welcome"}, {"session_id", s->session_id}, {"last_acked_seq", last_acked}}.dump());
  }

  void ScheduleCommit() {
    commit_timer_->expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(options_.commit_period_s)));
    commit_timer_->async_wait([this](boost::system::error_code ec) {
      if (ec) return;
      Commit();
      ScheduleCommit();
    });
  }

  void Commit() {
    if (!acks_enabled_) return;
    std::map<std::string, std::uint64_t> acks;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      for (auto& [id, pending] : pending_) {
        if (pending.empty()) continue;
        FakeSession& session = store_[id];
        session.committed.insert(session.committed.end(), pending.begin(), pending.end());
        session.last_acked = pending.back().seq;
        pending.clear();
        acks[id] = session.last_acked;
      }
    }
    for (auto& weak : sessions_) {
      auto s = weak.lock();
      if (s && acks.count(s->session_id)) Write(s, nlohmann::json{{"type", "ack"}, {"seq", acks[s->session_id]}}.dump());
    }
  }

  void Write(const SessionPtr& s, std::string text) {
    s->out.push_back(std::move(text));
    if (!s->writing) DoWrite(s);
  }
  void DoWrite(const SessionPtr& s) {
    s->writing = true;
    s->ws.text(true);
    s->ws.async_write(boost::asio::buffer(s->out.front()), [this, s](boost::system::error_code ec, std::size_t) {
      s->out.erase(s->out.begin());
      if (ec || s->out.empty()) {
        s->writing = false;
        return;
      }
      DoWrite(s);
    });
  }

  FakeIngestOptions options_;
  std::unique_ptr<boost::asio::io_context> ioc_;
  std::unique_ptr<tcp::acceptor> acceptor_;
  std::unique_ptr<boost::asio::steady_timer> commit_timer_;
  std::thread thread_;
  unsigned short port_ = 0;
  std::atomic<bool> acks_enabled_{true};
  std::vector<std::weak_ptr<Session>> sessions_;  // io thread only

  std::mutex mutex_;  // guards the store, which tests read from their own thread
  std::map<std::string, FakeSession> store_;
  std::map<std::string, std::vector<StoredMessage>> pending_;  // received, not yet committed
  std::size_t welcomes_ = 0;
  std::size_t refused_ = 0;
};

FakeIngestServer::FakeIngestServer(FakeIngestOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
FakeIngestServer::~FakeIngestServer() = default;
unsigned short FakeIngestServer::Start(unsigned short port) { return impl_->Start(port); }
void FakeIngestServer::Kill() { impl_->Kill(); }
unsigned short FakeIngestServer::port() const { return impl_->port(); }
void FakeIngestServer::set_acks_enabled(bool on) { impl_->set_acks_enabled(on); }
void FakeIngestServer::SendToAll(const nlohmann::json& message) { impl_->SendToAll(message); }
std::map<std::string, FakeSession> FakeIngestServer::sessions() { return impl_->sessions(); }
std::size_t FakeIngestServer::welcomes() { return impl_->welcomes(); }
std::size_t FakeIngestServer::refused() { return impl_->refused(); }

}  // namespace pslam::agent::testing
