// The dashboard's HTTP listener (Boost.Beast on Boost.Asio): the page at /, the JSON API under
// /api/, /metrics and the health probes, beside the gRPC server. With a client token, everything
// but the page, its script and stylesheet, /healthz and /readyz needs
// `Authorization: Bearer TOKEN` (docs/security.md, "The dashboard").
//
// Reading is asynchronous, so a slow or idle client holds a socket but no thread; the limits
// below (docs/security.md, "The dashboard's HTTP front") keep any one client address from
// holding the listener, and keep /healthz and /readyz answered whatever the others hold.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tessera::server {

class Coordinator;
class FarmMetrics;

struct HttpLimits {
  /// Connections one client address may have in each stage at once: heads in progress (the
  /// oldest is dropped for a new one) and requests past their head (more get 503). Probes are
  /// exempt. --http-connections-per-client.
  int connections_per_client = 16;
  /// From the connection to the end of the request's head (TLS handshake, request line,
  /// headers); a body then has as long again. --http-head-timeout.
  int64_t head_timeout_ms = 10'000;
  /// All connections together (file descriptors); 0: half the process's open-file limit,
  /// between 64 and 4096 (default_max_connections()).
  int max_connections = 0;
};

/// Half the soft RLIMIT_NOFILE, clamped to [64, 4096]: the rest stays for gRPC and the store.
int default_max_connections();

struct DashboardConfig {
  std::string token;  ///< the client token (--client-token or --token); empty: no token needed
  /// PEM certificate and key (the server's --tls-cert/--tls-key): both set, the dashboard
  /// serves HTTPS only; both empty, plain HTTP.
  std::string tls_cert_file, tls_key_file;
  /// Host names a request's Host and Origin may name besides IP literals, localhost and the
  /// listen host (--allowed-host: the names of proxies and ingresses in front of the server).
  std::vector<std::string> allowed_hosts;
  HttpLimits limits;
};

class DashboardServer {
 public:
  /// Throws std::runtime_error naming the files when the TLS certificate or key cannot be used,
  /// or naming the flag of a bad allowed host or limit. `coordinator` and `metrics` (fed by the
  /// coordinator through its UploadObserver) must outlive the server.
  DashboardServer(Coordinator& coordinator, const FarmMetrics& metrics, DashboardConfig config);
  ~DashboardServer();  ///< stops and joins
  DashboardServer(const DashboardServer&) = delete;
  DashboardServer& operator=(const DashboardServer&) = delete;

  /// Binds "HOST:PORT" ("[::1]:PORT" for IPv6; port 0 picks a free one) and starts serving on
  /// its threads. Returns the port bound. Throws std::runtime_error naming the address on
  /// failure. Call once.
  int start(const std::string& address);
  /// Stops accepting, drops requests still reading their head, lets the others finish (a few
  /// seconds at most), and joins. Idempotent.
  void stop();

  class Listener;  ///< the sockets, threads and limits (http_listener.h)

 private:
  Coordinator& coordinator_;
  const FarmMetrics& metrics_;
  DashboardConfig config_;
  std::shared_ptr<Listener> listener_;
};

}  // namespace tessera::server
