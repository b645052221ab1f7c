#include "dashboard/http_session.h"

// Boost 1.74's Asio uses std::exchange without including <utility> (GCC 12 no longer brings it).
#include <utility>
// clang-format off: the include above must come first
#include <algorithm>
#include <array>
#include <boost/beast/ssl.hpp>
#include <cctype>
#include <chrono>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>
// clang-format on

namespace tessera::server {
namespace {

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

std::string_view http_view(beast::string_view s) { return {s.data(), s.size()}; }

/// True for errors of the HTTP parser that mean a malformed request (answered 400), not a
/// connection that closed or timed out (closed without an answer).
bool is_http_parse_error(const beast::error_code& ec) {
  return ec.category() == bhttp::make_error_code(bhttp::error::bad_target).category() &&
         ec != bhttp::error::end_of_stream && ec != bhttp::error::partial_message;
}

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

std::shared_ptr<HttpSessionBase> make_http_session(DashboardServer::Listener& listener,
                                                  tcp::socket socket, asio::ssl::context* tls,
                                                  const std::string& address, uint64_t id) {
  if (tls) {
    using TlsStream = beast::ssl_stream<beast::tcp_stream>;
    return std::make_shared<HttpSession<TlsStream>>(
        listener, TlsStream(beast::tcp_stream(std::move(socket)), *tls), address, id);
  }
  return std::make_shared<HttpSession<beast::tcp_stream>>(
      listener, beast::tcp_stream(std::move(socket)), address, id);
}

}  // namespace tessera::server
