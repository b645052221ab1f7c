// What the dashboard, /api/store, /metrics and the CLI's warning say about the SQLite store:
// whether the whole-file check that follows an unclean stop is running, how far it has read,
// the damage it found, and why the store cannot write (docs/dashboard.md, "The store";
// docs/reliability.md, "A consistent database after any crash" and "A full disk").
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
  /// Why the store cannot write (StoreHealth::write_error: SQLite's "database or disk is full"
  /// naming the statement); "" when it can.
  std::string write_error;

  bool damaged() const { return !damage.empty(); }
  bool checking() const { return check == "checking"; }
  bool full() const { return !write_error.empty(); }
  /// "damaged", "full", "checking" or "ok": the banner the page shows (none for "ok").
  std::string summary() const {
    return damaged() ? "damaged" : full() ? "full" : checking() ? "checking" : "ok";
  }
};

/// The coordinator's store status now.
StoreStatus store_status(Coordinator& coordinator);

/// {"state", "check", "check_progress", "damage", "leasing", "write_error"} (docs/dashboard.md).
nlohmann::json store_json(const StoreStatus& s);

}  // namespace tessera::server
