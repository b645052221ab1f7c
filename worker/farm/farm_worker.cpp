#include "farm_worker.h"

#include <stdexcept>

#include "farm_worker_loop.h"
#include "stop_signal.h"

namespace tessera {

int run_farm_worker(const FarmWorkerConfig& config) {
  if (config.server.empty()) throw std::invalid_argument("--server: HOST:PORT is required");
  farm::StopSignal stop;  // before any thread starts: they inherit the blocked signals
  farm::FarmWorker worker(config, stop);
  return worker.run();
}

}  // namespace tessera
