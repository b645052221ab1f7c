// What the farm worker tells the server about itself when it registers: its default name and
// the ISA its renderer runs.
#pragma once

#include <string>

namespace tessera::farm {

/// "<host name>:<pid>": the name of a worker not given one.
std::string default_name();

/// The ISA Embree picks on this machine, found by building a one-sphere scene.
std::string probe_isa();

}  // namespace tessera::farm
