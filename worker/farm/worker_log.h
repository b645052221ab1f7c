// The farm worker's log: lines on stderr, each prefixed "tessera-worker: ".
#pragma once

#include <string>

namespace tessera::farm {

/// One line to stderr in one write (the delivery thread logs too).
void log(const std::string& line);

}  // namespace tessera::farm
