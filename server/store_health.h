// The store's health: the whole-file check (PRAGMA quick_check) after a start that followed no
// clean shutdown, run beside serving; what it found; readiness; and the clean shutdown's mark
// and WAL checkpoint. When the check finds damage the farm stops leasing and is no longer
// ready, and the server logs it.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "farm_events.h"
#include "farm_store.h"
#include "store/integrity.h"

namespace tessera::server {

class StoreHealth {
 public:
  /// Starts the check in the background when the store needs one (FarmStore::needs_check) and
  /// returns without waiting for it.
  StoreHealth(FarmStore& store, FarmEvents& events, const std::string& db_path);

  /// The check of this start: nullopt when none was due (the last server stopped cleanly),
  /// else its state.
  std::optional<IntegrityState> check() const;
  /// How much of the file the check has read, 0..1; nullopt when none was due.
  std::optional<double> check_progress() const;
  /// Blocks until the check of this start has ended (tests); nullopt when none was due.
  std::optional<IntegrityState> wait_for_check() const;
  /// The damage the check found (one line naming the file and what SQLite found), or "".
  std::string damage() const;
  /// `observer` is called once with damage() when the check finds damage, from the check's
  /// thread (at once, from this one, when it already has); it must not call back into the
  /// coordinator. Replacing it (nullptr) waits for a call in progress, so an observer is never
  /// called after it was replaced.
  void set_damage_observer(std::function<void(const std::string&)> observer);
  /// True when the store answers a query and no damage was found (for /readyz).
  bool ready();
  /// Stops the check if it still runs, marks the store as shut down cleanly unless a check was
  /// due and did not end `ok` (so the next start checks again), and checkpoints the WAL into the
  /// database file. Returns false when the checkpoint could not complete.
  bool checkpoint();

 private:
  /// The check found damage: log it, stop leasing, tell the observer (from the check's thread).
  void damaged(const std::string& message);

  FarmStore& store_;
  FarmEvents& events_;
  mutable std::mutex damage_mu_;
  std::string damage_;                                      ///< guarded by damage_mu_
  std::function<void(const std::string&)> damage_observer_;  ///< guarded by damage_mu_
  /// Last, so that it is stopped (its thread joined) before anything it calls is destroyed.
  std::unique_ptr<BackgroundIntegrityCheck> check_;
};

}  // namespace tessera::server
