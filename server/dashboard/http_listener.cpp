#include "dashboard/http_listener.h"

#include <sys/resource.h>

// Boost 1.74's Asio uses std::exchange without including <utility> (GCC 12 no longer brings it).
#include <utility>
// clang-format off: the include above must come first
#include <algorithm>
#include <chrono>
#include <iostream>
#include <stdexcept>
// clang-format on

#include "dashboard/http_session.h"

namespace tessera::server {
namespace {

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
      session = make_http_session(*this, std::move(socket), tls_ ? &*tls_ : nullptr, address,
                                  opened.id);
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

}  // namespace tessera::server
