#include "dashboard/http_server.h"

#include <httplib.h>

#include <stdexcept>

#include "cli/host_port.h"
#include "dashboard/api.h"

namespace tessera::server {

namespace {

std::unique_ptr<httplib::Server> make_listener(const DashboardConfig& config) {
  if (config.tls_cert_file.empty() && config.tls_key_file.empty()) {
    return std::make_unique<httplib::Server>();
  }
  auto https = std::make_unique<httplib::SSLServer>(config.tls_cert_file.c_str(),
                                                    config.tls_key_file.c_str());
  if (!https->is_valid()) {
    throw std::runtime_error("HTTPS: cannot use certificate " + config.tls_cert_file + " with key " +
                             config.tls_key_file + " (--tls-cert, --tls-key)");
  }
  return https;
}

}  // namespace

DashboardServer::DashboardServer(Coordinator& coordinator, const FarmMetrics& metrics,
                                 DashboardConfig config)
    : http_(make_listener(config)) {
  // httplib's default also sets SO_REUSEPORT, which lets the kernel hand the same port (even a
  // "free" one for port 0) to another process's listener, gRPC's included: a client would then
  // reach the wrong server. SO_REUSEADDR alone still allows a quick restart on the same port.
  http_->set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // One request per connection: a request refused on its headers (401, 411, 413, 415) leaves its
  // body unread, and the connection is closed rather than reading that body as the next request.
  http_->set_keep_alive_max_count(1);
  install_dashboard_routes(*http_, coordinator, metrics, std::move(config));
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
  int port = hp.port;
  if (port == 0) {
    port = http_->bind_to_any_port(hp.host);
    if (port < 0) port = 0;
  } else if (!http_->bind_to_port(hp.host, port)) {
    port = 0;
  }
  if (port <= 0) throw std::runtime_error("cannot listen on " + address + " (HTTP)");
  thread_ = std::thread([this] { http_->listen_after_bind(); });
  return port;
}

void DashboardServer::stop() {
  if (http_) http_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace tessera::server
