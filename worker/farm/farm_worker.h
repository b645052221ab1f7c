// `tessera-worker --server HOST:PORT`: a farm worker (docs/farm.md). It registers, leases work
// units (several per call when they are small: "Batched calls"), renders each in turn with every
// core it is given, uploads the compressed results (in one call when several),
// heartbeats while rendering, reconnects with exponential backoff when the server goes away, and
// on SIGTERM or SIGINT finishes (and delivers) the unit in hand, then exits 0; a second signal
// abandons the unit, hands it back to the server, and exits 0.
#pragma once

#include <filesystem>
#include <string>

#include "wire/transport_security.h"

namespace tessera {

struct FarmWorkerConfig {
  std::string server;  ///< "HOST:PORT" of tessera-server's gRPC endpoint
  int threads = 0;     ///< render threads; 0 = all cores
  /// Where scene bundles are cached by SHA-256; empty = $XDG_CACHE_HOME/tessera (or
  /// ~/.cache/tessera, or the system temp folder).
  std::filesystem::path cache_dir;
  std::string token;   ///< sent as `authorization: Bearer <token>` when not empty
  wire::ClientTls tls;  ///< TLS to the server; client cert/key for mutual TLS
  std::string name;    ///< shown by `tessera workers`; empty = "<host name>:<pid>"
};

/// Runs the worker until SIGTERM/SIGINT (returns 0) or an error retrying cannot fix, such as a
/// refused token (prints one line on stderr, returns 1). Blocks SIGTERM and SIGINT in the
/// calling thread and the threads it starts, and handles them itself.
int run_farm_worker(const FarmWorkerConfig& config);

}  // namespace tessera
