// What the dashboard, /api/store, /metrics and the CLI's warning say about the SQLite store:
// whether the whole-file check that follows an unclean stop is running, how far it has read,
// and the damage it found (docs/dashboard.md, "The store"; docs/reliability.md, "A consistent
// database after any crash").
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

namespace tessera::server {

class Coordinator;

struct StoreStatus {
  /// The check of this start: "none" (none was due: the last server stopped cleanly, or this
  /// start created the store), "checking", "ok", "damaged" or "interrupted".
  std::string check = "none";
  /// 0..1 of the file read while "checking" (an estimate); nullopt when no check was due.
  std::optional<double> check_progress;
  /// The damage found (one line naming the file and what SQLite reported); "" when none.
  std::string damage;
  /// False once the server hands out no more work (damage found, or shutting down).
  bool leasing = true;

  bool damaged() const { return !damage.empty(); }
  bool checking() const { return check == "checking"; }
  /// "damaged", "checking" or "ok": the banner the page shows (none for "ok").
  std::string summary() const { return damaged() ? "damaged" : checking() ? "checking" : "ok"; }
};

/// The coordinator's store status now.
StoreStatus store_status(Coordinator& coordinator);

/// {"state", "check", "check_progress", "damage", "leasing"} (docs/dashboard.md).
nlohmann::json store_json(const StoreStatus& s);

}  // namespace tessera::server
