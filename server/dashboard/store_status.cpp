#include "dashboard/store_status.h"

#include <nlohmann/json.hpp>

#include "coordinator.h"

namespace tessera::server {

StoreStatus store_status(Coordinator& coordinator) {
  StoreStatus s;
  if (const std::optional<IntegrityState> check = coordinator.store_check()) {
    s.check = integrity_state_name(*check);
    s.check_progress = coordinator.store_check_progress();
  }
  s.damage = coordinator.store_damage();
  s.leasing = !coordinator.changes().stopped();
  s.write_error = coordinator.store_write_error();
  return s;
}

nlohmann::json store_json(const StoreStatus& s) {
  return nlohmann::json{
      {"state", s.summary()},
      {"check", s.check},
      {"check_progress", s.check_progress ? nlohmann::json(*s.check_progress) : nullptr},
      {"damage", s.damage},
      {"leasing", s.leasing},
      {"write_error", s.write_error},
  };
}

}  // namespace tessera::server
