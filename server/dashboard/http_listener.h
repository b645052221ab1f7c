// The dashboard listener's insides, shared by its files: the Asio names, the listener's thread
// counts, the connection interface (HttpSessionBase) and DashboardServer::Listener, which owns
// the sockets, the threads and the connection table (http_listener.cpp; the sessions are
// http_session.cpp).
#pragma once

// Boost 1.74's Asio uses std::exchange without including <utility> (GCC 12 no longer brings it).
#include <utility>
// clang-format off: the include above must come first
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>
// clang-format on

#include "dashboard/api.h"
#include "dashboard/connection_table.h"
#include "dashboard/http_server.h"

namespace tessera::server {

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
// stop(): how long requests past their head may take to finish.
constexpr auto kHttpStopGrace = std::chrono::seconds(5);

/// One connection of the listener (HttpSession in http_session.cpp, plain or TLS). Declared
/// here: the Listener holds pointers to it.
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

}  // namespace tessera::server
