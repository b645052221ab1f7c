#include "dashboard/http_server.h"

#include <openssl/ssl.h>
#include <sys/resource.h>

// Boost 1.74's Asio uses std::exchange without including <utility> (GCC 12 no longer brings it).
#include <utility>
// clang-format off: the include above must come first
#include <algorithm>
#include <array>
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <cctype>
#include <chrono>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
// clang-format on

#include "cli/host_port.h"
#include "dashboard/api.h"
#include "dashboard/connection_table.h"

namespace tessera::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace bhttp = boost::beast::http;
using tcp = boost::asio::ip::tcp;

// Two threads do all the reading and writing: nothing on them blocks (handlers run on the pools
// below), so they only parse, copy and encrypt; the second keeps TLS handshakes from delaying
// everything else on a busy server.
constexpr int kHttpIoThreads = 2;
// The routes' handlers may block on the coordinator (SQLite, encoding a preview): they run on
// their own pool so that the I/O threads never wait for them. Eight, as many requests at once as
// the listener ever computed; more wait for a thread, holding a socket but no thread.
constexpr int kHttpHandlerThreads = 8;
// /readyz runs on a thread of its own, never queued behind slow API requests (/healthz, which
// reads nothing, is answered on the I/O thread).
constexpr int kHttpProbeThreads = 1;
// The request line and headers together; a longer head gets 431.
constexpr uint32_t kHttpMaxHeadBytes = 16 * 1024;
// A response must be written within this, plus a second per 256 KiB of body: a client reading
// slower than that (2 Mbit/s) loses the connection instead of holding it.
constexpr auto kHttpWriteGrace = std::chrono::seconds(30);
constexpr size_t kHttpMinWriteBytesPerS = 256 * 1024;
// TLS close_notify exchange after the response.
constexpr auto kHttpTlsShutdown = std::chrono::seconds(2);
// After the response, what the client still sends is read and dropped for at most this long and
// this much before the connection closes (finish()).
constexpr auto kHttpLinger = std::chrono::seconds(2);
constexpr size_t kHttpMaxLingerBytes = 256 * 1024;
// stop(): how long requests past their head may take to finish.
constexpr auto kHttpStopGrace = std::chrono::seconds(5);

std::string_view http_view(beast::string_view s) { return {s.data(), s.size()}; }

/// True for errors of the HTTP parser that mean a malformed request (answered 400), not a
/// connection that closed or timed out (closed without an answer).
bool is_http_parse_error(const beast::error_code& ec) {
  return ec.category() == bhttp::make_error_code(bhttp::error::bad_target).category() &&
         ec != bhttp::error::end_of_stream && ec != bhttp::error::partial_message;
}

/// The peer's address as the per-client limits count it: IPv4 clients on an IPv6 socket as
/// IPv4. "" when the connection has already gone.
std::string http_peer_address(const tcp::socket& socket) {
  beast::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  if (ec) return "";
  asio::ip::address address = peer.address();
  if (address.is_v6() && address.to_v6().is_v4_mapped()) {
    address = asio::ip::make_address_v4(asio::ip::v4_mapped, address.to_v6());
  }
  return address.to_string();
}

/// The TLS context of --tls-cert/--tls-key; throws naming the files when they cannot be used.
asio::ssl::context make_tls_context(const std::string& cert_file, const std::string& key_file) {
  asio::ssl::context tls(asio::ssl::context::tls_server);
  tls.set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                  asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                  asio::ssl::context::no_tlsv1_1);
  beast::error_code ec;
  std::string why;
  if (cert_file.empty() || key_file.empty()) {
    why = "both are needed";
  } else if (tls.use_certificate_chain_file(cert_file, ec); ec) {
    why = "certificate: " + ec.message();
  } else if (tls.use_private_key_file(key_file, asio::ssl::context::pem, ec); ec) {
    why = "key: " + ec.message();
  } else if (SSL_CTX_check_private_key(tls.native_handle()) != 1) {
    why = "the key does not match the certificate";
  }
  if (!why.empty()) {
    throw std::runtime_error("HTTPS: cannot use certificate " + cert_file + " with key " +
                             key_file + " (--tls-cert, --tls-key): " + why);
  }
  return tls;
}

}  // namespace

/// One connection of the listener (HttpSession below, plain or TLS). Outside the anonymous
/// namespace: the Listener, declared in the header, holds pointers to it.
class HttpSessionBase {
 public:
  virtual ~HttpSessionBase() = default;
  /// Starts reading the request, on the connection's strand.
  virtual void run() = 0;
  /// Closes the connection from any thread; what it was doing ends with an error.
  virtual void abort() = 0;
};

/// What the sessions share: the I/O context and its threads, the handler pools, the routes and
/// the connection table. Members are destroyed in reverse order: the I/O context (and with it any
/// session still queued on it) before the table, the TLS context and the routes they use.
class DashboardServer::Listener {
 public:
  Listener(HttpLimits limits, std::optional<asio::ssl::context> tls)
      : limits_(limits),
        table_(limits.connections_per_client, limits.max_connections > 0
                                                  ? limits.max_connections
                                                  : default_max_connections()),
        tls_(std::move(tls)) {}

  int start(const tcp::endpoint& endpoint, DashboardRoutes routes);
  void stop();

  // For the sessions.
  const DashboardRoutes& routes() const { return *routes_; }
  const HttpLimits& limits() const { return limits_; }
  asio::thread_pool& pool(bool probe) { return probe ? probe_pool_ : handler_pool_; }
  ConnectionTable::Admission head_done(uint64_t id, bool exempt) {
    std::lock_guard lock(mu_);
    return table_.head_done(id, exempt);
  }
  void closed(uint64_t id) {
    std::lock_guard lock(mu_);
    table_.close(id);
    sessions_.erase(id);
  }

 private:
  void accept();
  void on_accept(beast::error_code ec, tcp::socket socket);
  /// The session of a new connection, registered; nullptr when the table refuses it.
  std::shared_ptr<HttpSessionBase> make_session(tcp::socket socket, const std::string& address);

  const HttpLimits limits_;
  std::mutex mu_;  ///< guards table_, sessions_
  ConnectionTable table_;
  std::map<uint64_t, std::weak_ptr<HttpSessionBase>> sessions_;
  std::optional<DashboardRoutes> routes_;
  std::optional<asio::ssl::context> tls_;
  asio::thread_pool handler_pool_{kHttpHandlerThreads};
  asio::thread_pool probe_pool_{kHttpProbeThreads};
  asio::io_context ioc_{kHttpIoThreads};
  tcp::acceptor acceptor_{ioc_};
  asio::steady_timer accept_retry_{ioc_};
  std::vector<std::thread> io_threads_;
  bool running_ = false;
};

namespace {

/// One connection, one request (`Connection: close`): the head under the head deadline (TLS
/// handshake included), the admission by the connection table, the checks on the head, the body
/// (at most DashboardRoutes::kMaxBodyBytes, as long again), the handler on a pool, the answer.
/// Everything but the handler runs on the connection's strand.
template <class Stream>
class HttpSession : public HttpSessionBase,
                    public std::enable_shared_from_this<HttpSession<Stream>> {
  static constexpr bool kTls = !std::is_same_v<Stream, beast::tcp_stream>;

 public:
  HttpSession(DashboardServer::Listener& listener, Stream stream, std::string address, uint64_t id)
      : listener_(listener), stream_(std::move(stream)), address_(std::move(address)), id_(id) {}
  ~HttpSession() override {
    if (!closed_) listener_.closed(id_);
  }

  void run() override {
    asio::dispatch(stream_.get_executor(), [self = this->shared_from_this()] { self->begin(); });
  }
  void abort() override {
    asio::post(stream_.get_executor(), [self = this->shared_from_this()] { self->close(); });
  }

 private:
  beast::tcp_stream& tcp() { return beast::get_lowest_layer(stream_); }
  std::chrono::milliseconds head_timeout() const {
    return std::chrono::milliseconds(listener_.limits().head_timeout_ms);
  }

  void begin() {
    if (closed_) return;
    tcp().expires_after(head_timeout());  // the handshake and the head together
    if constexpr (kTls) {
      stream_.async_handshake(asio::ssl::stream_base::server,
                              [self = this->shared_from_this()](beast::error_code ec) {
                                if (ec) return self->close();
                                self->read_head();
                              });
    } else {
      read_head();
    }
  }

  void read_head() {
    head_.emplace();
    head_->header_limit(kHttpMaxHeadBytes);
    // The routes judge Content-Length (411, 413) themselves. (Not boost::none: Beast 1.74 then
    // refuses every body, comparing the length with an empty optional.)
    head_->body_limit(std::numeric_limits<std::uint64_t>::max());
    bhttp::async_read_header(stream_, buffer_, *head_,
                             [self = this->shared_from_this()](beast::error_code ec, size_t) {
                               self->on_head(ec);
                             });
  }

  void on_head(beast::error_code ec) {
    if (ec == bhttp::error::bad_content_length) return on_bad_content_length();
    if (ec == bhttp::error::header_limit) {
      return refuse(431, "the request's head may be at most " +
                             std::to_string(kHttpMaxHeadBytes) + " bytes");
    }
    if (ec) {
      if (is_http_parse_error(ec)) return refuse(400, "bad request: " + ec.message());
      return close();  // closed, reset, or the head deadline passed
    }
    const auto& message = head_->get();
    version_ = message.version();
    req_.method = std::string(http_view(message.method_string()));
    split_target(http_view(message.target()), req_.path, req_.params);
    for (const auto& field : message) {
      req_.headers.emplace_back(std::string(http_view(field.name_string())),
                                std::string(http_view(field.value())));
    }
    on_request_head();
  }

  /// Beast refuses a Content-Length it cannot read (not a number, or too large for 64 bits)
  /// before the routes see it. The head is parsed again without that header, which then goes to
  /// the routes as sent, so that the answer follows the routes' order (the token's 401 before
  /// the length's 413). The parser has taken the request line out of the buffer and left the
  /// fields, all of them (it reads none before it has the whole head).
  void on_bad_content_length() {
    const auto& parsed = head_->get();
    std::string stripped = std::string(http_view(parsed.method_string())) + " " +
                           std::string(http_view(parsed.target())) + " HTTP/" +
                           std::to_string(parsed.version() / 10) + "." +
                           std::to_string(parsed.version() % 10) + "\r\n";
    std::string_view raw(static_cast<const char*>(buffer_.data().data()), buffer_.data().size());
    if (raw.starts_with(stripped)) raw.remove_prefix(stripped.size());
    // The fields end with an empty line: at 0 when there is no other field.
    const size_t end = raw.starts_with("\r\n") ? 0 : raw.find("\r\n\r\n");
    if (end == std::string_view::npos || parsed.method_string().empty()) {
      return refuse(400, "bad request: bad Content-Length");
    }
    std::vector<std::string> lengths;
    size_t at = 0;
    while (end > 0 && at < end + 2) {
      const size_t eol = raw.find("\r\n", at);
      const std::string_view line = raw.substr(at, eol - at);
      at = eol + 2;
      static constexpr std::string_view kName = "content-length:";
      if (line.size() >= kName.size() &&
          std::equal(kName.begin(), kName.end(), line.begin(),
                     [](char a, char b) { return a == std::tolower(static_cast<unsigned char>(b)); })) {
        std::string_view value = line.substr(kName.size());
        while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
        while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
        lengths.emplace_back(value);
        continue;
      }
      stripped.append(line).append("\r\n");
    }
    stripped += "\r\n";
    head_.emplace();
    head_->header_limit(kHttpMaxHeadBytes);
    beast::error_code ec;
    head_->put(asio::buffer(stripped), ec);
    if (ec || !head_->is_header_done() || lengths.size() != 1) {
      return refuse(400, "bad request: bad Content-Length");
    }
    head_->get().set(bhttp::field::content_length, lengths.front());
    bad_content_length_ = true;
    on_head({});
  }

  void on_request_head() {
    req_.remote_address = address_;
    probe_ = DashboardRoutes::is_probe(req_.path);
    switch (listener_.head_done(id_, probe_)) {
      case ConnectionTable::Admission::client_full:
        return refuse(503, "too many requests at once from " + address_ + " (at most " +
                               std::to_string(listener_.limits().connections_per_client) +
                               " per client: --http-connections-per-client)");
      case ConnectionTable::Admission::server_full:
        return refuse(503, "the server holds as many requests as it may: try again shortly");
      case ConnectionTable::Admission::admitted:
      case ConnectionTable::Admission::exempt:
        break;
    }
    HttpResponse res;
    if (listener_.routes().answer_head(req_, res)) return write(std::move(res));
    if (bad_content_length_) return refuse(400, "bad request: bad Content-Length");
    if (DashboardRoutes::carries_body(req_.method)) return read_body();
    run_handler();
  }

  void read_body() {
    body_.emplace(std::move(*head_));
    head_.reset();
    body_->body_limit(DashboardRoutes::kMaxBodyBytes);
    tcp().expires_after(head_timeout());
    bhttp::async_read(stream_, buffer_, *body_,
                      [self = this->shared_from_this()](beast::error_code ec, size_t) {
                        self->on_body(ec);
                      });
  }

  void on_body(beast::error_code ec) {
    if (ec == bhttp::error::body_limit) {
      HttpResponse res;
      DashboardRoutes::body_too_large(res);
      return write(std::move(res));
    }
    if (ec) {
      if (is_http_parse_error(ec)) return refuse(400, "bad request body: " + ec.message());
      return close();
    }
    req_.body = body_->release().body();
    run_handler();
  }

  void run_handler() {
    if (DashboardRoutes::answers_without_waiting(req_.path)) {
      HttpResponse res;
      listener_.routes().answer(req_, res);
      return write(std::move(res));
    }
    tcp().expires_never();  // the handler may take its time; nothing is read meanwhile
    asio::post(listener_.pool(probe_), [self = this->shared_from_this()] {
      HttpResponse res;
      try {
        self->listener_.routes().answer(self->req_, res);
      } catch (const std::exception& e) {
        set_json_error(res, 500, e.what());
      }
      asio::post(self->stream_.get_executor(), [self, res = std::move(res)]() mutable {
        self->write(std::move(res));
      });
    });
  }

  void refuse(int status, const std::string& message) {
    listener_.head_done(id_, /*exempt=*/true);  // a short answer, then closed
    HttpResponse res;
    set_json_error(res, status, message);
    if (status == 503) res.set_header("Retry-After", "1");
    write(std::move(res));
  }

  void write(HttpResponse res) {
    if (closed_) return;
    response_ = {};
    response_.version(version_);
    response_.result(unsigned(res.status));
    for (auto& [name, value] : res.headers) response_.set(name, value);
    if (!res.content_type.empty()) response_.set(bhttp::field::content_type, res.content_type);
    response_.keep_alive(false);  // one request per connection
    const size_t size = res.body.size();
    if (req_.method == "HEAD") {
      response_.content_length(size);
    } else {
      response_.body() = std::move(res.body);
      response_.prepare_payload();
    }
    tcp().expires_after(kHttpWriteGrace + std::chrono::seconds(size / kHttpMinWriteBytesPerS));
    bhttp::async_write(stream_, response_,
                       [self = this->shared_from_this()](beast::error_code ec, size_t) {
                         if (ec) return self->close();
                         self->finish();
                       });
  }

  void finish() {
    if constexpr (kTls) {
      tcp().expires_after(kHttpTlsShutdown);
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) { self->close(); });
    } else {
      // A lingering close: what the client still sends (the body of a refused request) is read
      // and dropped for a moment, since closing with unread data resets the connection, and the
      // client could lose the answer before reading it.
      beast::error_code ignored;
      tcp().socket().shutdown(tcp::socket::shutdown_send, ignored);
      tcp().expires_after(kHttpLinger);
      drain();
    }
  }

  void drain() {
    tcp().async_read_some(asio::buffer(drain_buffer_),
                          [self = this->shared_from_this()](beast::error_code ec, size_t n) {
                            self->drained_bytes_ += n;
                            if (ec || self->drained_bytes_ > kHttpMaxLingerBytes) {
                              return self->close();
                            }
                            self->drain();
                          });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    tcp().close();  // the socket and the deadline's timer
    listener_.closed(id_);
  }

  DashboardServer::Listener& listener_;
  Stream stream_;
  const std::string address_;
  const uint64_t id_;
  beast::flat_buffer buffer_;
  std::optional<bhttp::request_parser<bhttp::empty_body>> head_;
  std::optional<bhttp::request_parser<bhttp::string_body>> body_;
  unsigned version_ = 11;
  HttpRequest req_;
  bool probe_ = false;
  bool bad_content_length_ = false;
  std::array<char, 4096> drain_buffer_;
  size_t drained_bytes_ = 0;
  bool closed_ = false;
  bhttp::response<bhttp::string_body> response_;
};

}  // namespace

int default_max_connections() {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 4096;
  return int(std::clamp<rlim_t>(limit.rlim_cur / 2, 64, 4096));
}

std::shared_ptr<HttpSessionBase> DashboardServer::Listener::make_session(
    tcp::socket socket, const std::string& address) {
  std::shared_ptr<HttpSessionBase> session;
  std::vector<std::shared_ptr<HttpSessionBase>> dropped;
  {
    std::lock_guard lock(mu_);
    const ConnectionTable::Opened opened = table_.open(address);
    for (const uint64_t id : opened.drop) {
      auto it = sessions_.find(id);
      if (it == sessions_.end()) continue;
      if (auto old = it->second.lock()) dropped.push_back(std::move(old));
      sessions_.erase(it);
    }
    if (opened.id != 0) {
      if (tls_) {
        using TlsStream = beast::ssl_stream<beast::tcp_stream>;
        session = std::make_shared<HttpSession<TlsStream>>(
            *this, TlsStream(beast::tcp_stream(std::move(socket)), *tls_), address, opened.id);
      } else {
        session = std::make_shared<HttpSession<beast::tcp_stream>>(
            *this, beast::tcp_stream(std::move(socket)), address, opened.id);
      }
      sessions_[opened.id] = session;
    }
  }
  for (const auto& old : dropped) old->abort();
  return session;
}

void DashboardServer::Listener::accept() {
  acceptor_.async_accept(asio::make_strand(ioc_), [this](beast::error_code ec, tcp::socket socket) {
    on_accept(ec, std::move(socket));
  });
}

void DashboardServer::Listener::on_accept(beast::error_code ec, tcp::socket socket) {
  if (!acceptor_.is_open() || ec == asio::error::operation_aborted) return;
  if (ec) {
    // Out of file descriptors or the like: try again shortly rather than spin.
    accept_retry_.expires_after(std::chrono::milliseconds(100));
    accept_retry_.async_wait([this](beast::error_code wait_ec) {
      if (!wait_ec && acceptor_.is_open()) accept();
    });
    return;
  }
  const std::string address = http_peer_address(socket);
  if (!address.empty()) {
    // Refused (every slot holds a request past its head): the socket closes here.
    if (auto session = make_session(std::move(socket), address)) session->run();
  }
  accept();
}

int DashboardServer::Listener::start(const tcp::endpoint& endpoint, DashboardRoutes routes) {
  routes_.emplace(std::move(routes));
  acceptor_.open(endpoint.protocol());
  // SO_REUSEPORT would let the kernel hand the same port (even a "free" one for port 0) to
  // another process's listener, gRPC's included: a client would then reach the wrong server.
  // SO_REUSEADDR alone (asio's reuse_address) still allows a quick restart on the same port.
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(asio::socket_base::max_listen_connections);
  const int port = acceptor_.local_endpoint().port();
  accept();
  running_ = true;
  for (int i = 0; i < kHttpIoThreads; ++i) {
    io_threads_.emplace_back([this] {
      for (;;) {
        try {
          ioc_.run();
          return;
        } catch (const std::exception& e) {
          std::cerr << "tessera-server: dashboard: " << e.what() << std::endl;
        }
      }
    });
  }
  return port;
}

void DashboardServer::Listener::stop() {
  if (!running_) return;
  running_ = false;
  asio::post(ioc_, [this] {
    beast::error_code ignored;
    acceptor_.close(ignored);
    accept_retry_.cancel();
  });
  // Requests still reading their head are dropped; the others get kHttpStopGrace to finish.
  auto abort_sessions = [this](bool heads_only) {
    std::vector<std::shared_ptr<HttpSessionBase>> sessions;
    {
      std::lock_guard lock(mu_);
      const std::vector<uint64_t> heads = table_.heads();
      for (const auto& [id, weak] : sessions_) {
        if (heads_only && std::find(heads.begin(), heads.end(), id) == heads.end()) continue;
        if (auto session = weak.lock()) sessions.push_back(std::move(session));
      }
    }
    for (const auto& session : sessions) session->abort();
  };
  abort_sessions(true);
  const auto deadline = std::chrono::steady_clock::now() + kHttpStopGrace;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard lock(mu_);
      if (sessions_.empty()) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  abort_sessions(false);
  handler_pool_.join();
  probe_pool_.join();
  ioc_.stop();
  for (std::thread& t : io_threads_) t.join();
  io_threads_.clear();
}

DashboardServer::DashboardServer(Coordinator& coordinator, const FarmMetrics& metrics,
                                 DashboardConfig config)
    : coordinator_(coordinator), metrics_(metrics), config_(std::move(config)) {
  for (const std::string& name : config_.allowed_hosts) {
    try {
      HostCheck::normalise_name(name);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--allowed-host: ") + e.what());
    }
  }
  std::optional<asio::ssl::context> tls;
  if (!config_.tls_cert_file.empty() || !config_.tls_key_file.empty()) {
    tls.emplace(make_tls_context(config_.tls_cert_file, config_.tls_key_file));
  }
  listener_ = std::make_shared<Listener>(config_.limits, std::move(tls));
}

DashboardServer::~DashboardServer() { stop(); }

int DashboardServer::start(const std::string& address) {
  cli::HostPort hp;
  try {
    hp = cli::parse_host_port(address);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("--http: ") + e.what());
  }
  if (hp.unix_socket) throw std::runtime_error("--http: " + address + ": a unix: socket is gRPC only");
  DashboardRoutes routes(coordinator_, metrics_, config_,
                         HostCheck(hp.host, config_.allowed_hosts));
  tcp::endpoint endpoint;
  try {
    asio::io_context resolver_context;
    tcp::resolver resolver(resolver_context);
    const auto endpoints =
        resolver.resolve(hp.host, std::to_string(hp.port), tcp::resolver::passive);
    if (endpoints.empty()) throw std::runtime_error("no address");
    endpoint = endpoints.begin()->endpoint();
    return listener_->start(endpoint, std::move(routes));
  } catch (const boost::system::system_error&) {
    throw std::runtime_error("cannot listen on " + address + " (HTTP)");
  } catch (const std::runtime_error&) {
    throw std::runtime_error("cannot listen on " + address + " (HTTP)");
  }
}

void DashboardServer::stop() {
  if (listener_) listener_->stop();
}

}  // namespace tessera::server
