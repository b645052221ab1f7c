#include "worker_log.h"

#include <iostream>

namespace tessera::farm {

void log(const std::string& line) { std::cerr << ("tessera-worker: " + line + "\n") << std::flush; }

}  // namespace tessera::farm
