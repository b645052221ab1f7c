// The dashboard's HTTP listener (cpp-httplib): the page at /, the JSON API under /api/, /metrics
// and the health probes, served from a thread pool beside the gRPC server. Reads are open; every
// request that changes state needs `Authorization: Bearer TOKEN` when the server has a token.
#pragma once

#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace tessera::server {

class Coordinator;

struct DashboardConfig {
  std::string token;  ///< the server's --token; empty: state changes need no token
};

class DashboardServer {
 public:
  DashboardServer(Coordinator& coordinator, DashboardConfig config);
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
