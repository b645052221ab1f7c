// The units a LeaseUnit answer hands this worker, one lease each.
#pragma once

#include <string>
#include <vector>

#include "tessera/v1/worker_service.pb.h"

namespace tessera::farm {

/// One unit of a LeaseUnit answer.
struct HeldUnit {
  std::string lease_id;
  v1::WorkUnit unit;
};

/// The units of an answer: `leases` (a server that knows max_units), or the single-unit fields
/// (a server from before batched calls ignores max_units).
std::vector<HeldUnit> held_units(const v1::LeaseUnitResponse& lease);

}  // namespace tessera::farm
