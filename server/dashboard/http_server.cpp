#include "dashboard/http_server.h"

#include <httplib.h>

#include <stdexcept>

#include "dashboard/api.h"

namespace tessera::server {

HostPort parse_http_address(const std::string& address) {
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == address.size()) {
    throw std::runtime_error("--http: expected HOST:PORT (got \"" + address + "\")");
  }
  HostPort hp;
  hp.host = address.substr(0, colon);
  if (hp.host.size() >= 2 && hp.host.front() == '[' && hp.host.back() == ']') {
    hp.host = hp.host.substr(1, hp.host.size() - 2);
  }
  const std::string port = address.substr(colon + 1);
  size_t used = 0;
  try {
    hp.port = std::stoi(port, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != port.size() || hp.port < 0 || hp.port > 65535) {
    throw std::runtime_error("--http: port must be 0..65535 (got \"" + port + "\")");
  }
  return hp;
}

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

DashboardServer::DashboardServer(Coordinator& coordinator, DashboardConfig config)
    : http_(make_listener(config)) {
  // httplib's default also sets SO_REUSEPORT, which lets the kernel hand the same port (even a
  // "free" one for port 0) to another process's listener, gRPC's included: a client would then
  // reach the wrong server. SO_REUSEADDR alone still allows a quick restart on the same port.
  http_->set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  install_dashboard_routes(*http_, coordinator, std::move(config));
}

DashboardServer::~DashboardServer() { stop(); }

int DashboardServer::start(const std::string& address) {
  const HostPort hp = parse_http_address(address);
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
