// The dashboard's HTTP listener (cpp-httplib): the page at /, the JSON API under /api/, /metrics
// and the health probes, served from a thread pool beside the gRPC server. With a client token,
// everything but the page, its script and stylesheet, /healthz and /readyz needs
// `Authorization: Bearer TOKEN` (docs/security.md, "The dashboard").
#pragma once

#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace tessera::server {

class Coordinator;
class FarmMetrics;

struct DashboardConfig {
  std::string token;  ///< the client token (--client-token or --token); empty: no token needed
  /// PEM certificate and key (the server's --tls-cert/--tls-key): both set, the dashboard
  /// serves HTTPS only; both empty, plain HTTP.
  std::string tls_cert_file, tls_key_file;
};

class DashboardServer {
 public:
  /// Throws std::runtime_error naming the files when the TLS certificate or key cannot be used.
  /// `metrics` (fed by the coordinator through its UploadObserver) must outlive the server.
  DashboardServer(Coordinator& coordinator, const FarmMetrics& metrics, DashboardConfig config);
  ~DashboardServer();  ///< stops and joins
  DashboardServer(const DashboardServer&) = delete;
  DashboardServer& operator=(const DashboardServer&) = delete;

  /// Binds "HOST:PORT" ("[::1]:PORT" for IPv6; port 0 picks a free one) and starts serving on a
  /// thread. Returns the port bound. Throws std::runtime_error naming the address on failure.
  int start(const std::string& address);
  /// Stops accepting, finishes the requests in flight and joins. Idempotent.
  void stop();

 private:
  std::unique_ptr<httplib::Server> http_;
  std::thread thread_;
};

}  // namespace tessera::server
