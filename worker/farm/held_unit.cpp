#include "held_unit.h"

namespace tessera::farm {

std::vector<HeldUnit> held_units(const v1::LeaseUnitResponse& lease) {
  std::vector<HeldUnit> held;
  if (!lease.leased()) return held;
  for (const v1::UnitLease& l : lease.leases()) held.push_back({l.lease_id(), l.unit()});
  if (held.empty() && !lease.lease_id().empty()) held.push_back({lease.lease_id(), lease.unit()});
  return held;
}

}  // namespace tessera::farm
