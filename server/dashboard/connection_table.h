// Who holds the dashboard's connections, per client address: the bookkeeping that keeps slow or
// idle clients from starving the listener, and keeps the health probes answered whatever other
// clients hold (docs/security.md, "The dashboard's HTTP front").
//
// A connection is first a head in progress (TLS handshake, request line and headers), then, once
// its head is complete and its path known, either a probe (/healthz, /readyz: always served) or an
// admitted request (body, handler, response). The limits:
//  - heads in progress per address: at most `per_client`; a new connection from that address
//    drops the oldest of them. A client opening connections and never finishing them only ever
//    loses its own, and a new connection (a probe's) is always read;
//  - admitted requests per address: at most `per_client`; past it the request is refused (503);
//  - all connections: at most `max_total` (file descriptors); a new connection past it drops the
//    oldest head in progress of any address, and is refused only when there is none;
//  - admitted requests of all addresses: at most max_total - reserve, so that `reserve` slots are
//    always left to heads in progress (and with them the probes).
// Not thread-safe: the listener calls it under its lock.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

namespace tessera::server {

class ConnectionTable {
 public:
  /// `per_client` >= 1; `max_total` >= 2 (the reserve is an eighth of it, at least 1).
  ConnectionTable(int per_client, int max_total);

  struct Opened {
    uint64_t id = 0;              ///< 0: refused, close the connection at once
    std::vector<uint64_t> drop;  ///< connections (heads in progress) to close for this one
  };
  /// A new connection from `address`: a head in progress.
  Opened open(const std::string& address);

  enum class Admission { admitted, exempt, client_full, server_full };
  /// The head of `id` is complete. An `exempt` request (a probe) is always let through and
  /// counted in no limit but the total; otherwise `admitted`, or refused for its address
  /// (`client_full`) or for the server (`server_full`). Unknown ids (dropped) are `exempt`.
  Admission head_done(uint64_t id, bool exempt);

  /// The connection has closed; unknown ids (already dropped) are ignored.
  void close(uint64_t id);

  /// The connections still reading their head, oldest first.
  std::vector<uint64_t> heads() const;

  size_t connections() const { return stage_.size(); }
  size_t admitted() const { return admitted_total_; }
  int per_client() const { return per_client_; }
  int max_total() const { return max_total_; }

 private:
  enum class Stage { head, admitted, exempt };
  struct Client {
    std::deque<uint64_t> heads;  ///< heads in progress, oldest first
    int admitted = 0;
  };
  struct Entry {
    std::string address;
    Stage stage = Stage::head;
  };
  void forget_head(const std::string& address, uint64_t id);
  void drop_client_if_idle(const std::string& address);

  int per_client_, max_total_, max_admitted_;
  uint64_t next_id_ = 1;
  size_t admitted_total_ = 0;
  std::map<uint64_t, Entry> stage_;  ///< every open connection; ids grow, so the first is oldest
  std::map<std::string, Client> clients_;
};

}  // namespace tessera::server
