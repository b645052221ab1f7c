// The store's health: the whole-file check (PRAGMA quick_check) after a start that followed no
// clean shutdown, run beside serving; what it found; whether the store can write (a full disk);
// readiness; and the clean shutdown's mark and WAL checkpoint. When the check finds damage the
// farm stops leasing and is no longer ready, and the server logs it. While the store cannot
// write the server is not ready and says why; it serves reads all the same.
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
  /// Why the store cannot write, or "": the message of the last write that failed for lack of
  /// space (SQLITE_FULL: a full disk, or the database at its max_page_count), until a probe
  /// write of kProbeBytes commits again, tried at most once per kProbeIntervalMs of the farm's
  /// clock while the error stands. Logs each change. Takes the store's lock only after such a
  /// failure: a healthy store's answer reads one counter.
  std::string write_error();
  /// "" when the store answers a query, no damage was found and it can write (write_error);
  /// else why not, in one line (for /readyz).
  std::string unready_reason();
  /// unready_reason() is "".
  bool ready() { return unready_reason().empty(); }

  /// The probe's blob: a few pages more than a result of a 32-px tile (about 19 KB), so a store
  /// that takes the probe takes the uploads that failed.
  static constexpr int kProbeBytes = 64 * 1024;
  static constexpr int64_t kProbeIntervalMs = 2000;
  /// Stops the check if it still runs, marks the store as shut down cleanly unless a check was
  /// due and did not end `ok` (so the next start checks again), and checkpoints the WAL into the
  /// database file. Returns false when the checkpoint could not complete.
  bool checkpoint();

 private:
  /// The check found damage: log it, stop leasing, tell the observer (from the check's thread).
  void damaged(const std::string& message);
  /// Writes and commits kProbeBytes in a table of its own, then drops it. True when both
  /// committed. Requires the store's lock.
  bool probe_write();

  FarmStore& store_;
  FarmEvents& events_;
  mutable std::mutex damage_mu_;
  std::string damage_;                                      ///< guarded by damage_mu_
  std::function<void(const std::string&)> damage_observer_;  ///< guarded by damage_mu_
  // Taken inside the store's lock, never the other way round.
  std::mutex write_mu_;
  uint64_t space_failures_seen_ = 0;  ///< SpaceFailures::count when last looked at; write_mu_
  std::string write_error_;           ///< why the store cannot write, or ""; write_mu_
  int64_t probed_unix_ms_ = 0;        ///< when write_error_ was set or last probed; write_mu_
  /// Last, so that it is stopped (its thread joined) before anything it calls is destroyed.
  std::unique_ptr<BackgroundIntegrityCheck> check_;
};

}  // namespace tessera::server
