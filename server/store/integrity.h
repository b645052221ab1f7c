// Start-up and shutdown care of the SQLite store: refuse to serve a damaged database, and leave
// a clean one behind (docs/reliability.md, "Worker health and shutdown").
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "store/sqlite.h"

namespace tessera::server {

/// The store is damaged; what() says which file, what SQLite found, and what to do.
class StoreCorrupt : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Runs `PRAGMA quick_check` and throws StoreCorrupt unless it answers exactly "ok". A
/// SQLITE_CORRUPT or SQLITE_NOTADB error while checking is reported the same way. quick_check
/// reads every page (torn pages, malformed records, the freelist, NOT NULL and CHECK
/// constraints) but does not match each index against its table, which integrity_check does
/// at O(N log N): about 2.6 times its CPU on a 68 MB store (BENCHMARKS.md, "Server start-up time").
void check_integrity(Database& db, const std::string& path);

/// What the whole-file check found so far (BackgroundIntegrityCheck::state).
enum class IntegrityState {
  checking,     ///< quick_check is still reading the file
  ok,           ///< it read the whole file and found nothing
  damaged,      ///< it found damage (message() says what); the server stops leasing
  interrupted,  ///< stopped before it finished (shutdown): the next start checks again
};

/// "checking", "ok", "damaged", "interrupted".
const char* integrity_state_name(IntegrityState state);

/// check_integrity in the background, on its own connection to `path` (a read transaction in
/// WAL mode: the server's writer goes on while it reads a snapshot of the file). Started after
/// an unclean stop, so that the server serves at once instead of spending seconds per hundred
/// MB before it listens (docs/reliability.md, "A consistent database after any crash").
/// `on_end` is called once, from the check's thread, when the check ends: with `damaged` and
/// the one-line message of corrupt_store_message when it found damage (or its connection met
/// SQLITE_CORRUPT or SQLITE_NOTADB), `ok` and "", or `interrupted` (by stop(), message "", or
/// by an error that kept it from finishing, message "check failed: ..."). It must not call
/// back into this object. The destructor stops the check (stop()).
class BackgroundIntegrityCheck {
 public:
  using EndCallback = std::function<void(IntegrityState, const std::string&)>;
  BackgroundIntegrityCheck(std::string path, EndCallback on_end);
  ~BackgroundIntegrityCheck();
  BackgroundIntegrityCheck(const BackgroundIntegrityCheck&) = delete;
  BackgroundIntegrityCheck& operator=(const BackgroundIntegrityCheck&) = delete;

  IntegrityState state() const;
  /// The damage found (corrupt_store_message), or an error that kept the check from running;
  /// empty otherwise.
  std::string message() const;
  /// How much of the file the check has read, 0..1: the pages its connection has read from the
  /// file (SQLite's cache misses, sampled every few thousand VM steps) over the file's page count
  /// when it began; quick_check reads each page about once. 1 once it passed; 0 before it began
  /// reading. For the dashboard's "checking the database" banner (docs/dashboard.md).
  double progress() const;
  /// Blocks until the check has ended (any state but `checking`) and its `on_end` has returned,
  /// and returns its state.
  IntegrityState wait() const;
  /// Interrupts the check (sqlite3_interrupt on its connection) and joins its thread: within
  /// milliseconds, not the file's whole read. A check that had ended keeps its state; one still
  /// reading becomes `interrupted`. Idempotent.
  void stop();

 private:
  void run();
  void finish(IntegrityState state, std::string message);

  const std::string path_;
  const EndCallback on_end_;
  mutable std::mutex mu_;
  mutable std::condition_variable ended_;
  IntegrityState state_ = IntegrityState::checking;
  std::string message_;
  bool stop_requested_ = false;
  Database* db_ = nullptr;  ///< the check's connection while it is open (guarded by mu_)
  std::atomic<int64_t> pages_total_{0};  ///< PRAGMA page_count when the check began
  std::atomic<int64_t> pages_read_{0};   ///< the check connection's cache misses so far
  std::thread thread_;      ///< last: started when everything above is ready
};

/// The one-line message for a damaged store at `path`, with SQLite's `detail`.
std::string corrupt_store_message(const std::string& path, const std::string& detail);

/// True for SQLite's "this file is damaged" result codes (SQLITE_CORRUPT, SQLITE_NOTADB).
bool is_corruption(const SqliteError& e);

/// Start-up: true when the last server on `db` stopped cleanly (it called
/// leave_clean_shutdown_mark as its last write), false after a crash, a SIGKILL or a power loss,
/// and for a store from before the mark. Either way the mark is cleared (committed) before it
/// returns, so a crash from now on is seen by the next start. The mark is the database header's
/// `PRAGMA user_version` (nothing else uses it): reading it reads page 1 only. Throws StoreCorrupt
/// when SQLite finds the file damaged.
bool take_clean_shutdown_mark(Database& db, const std::string& path);

/// Shutdown, after the last write of the server's life: marks the store as left cleanly, so the
/// next start skips the whole-file check (check_integrity).
void leave_clean_shutdown_mark(Database& db);

/// PRAGMA wal_checkpoint(TRUNCATE): copies the WAL into the database file and empties it, so a
/// stopped server leaves one self-contained file. Returns false when readers kept it busy.
bool checkpoint_wal(Database& db);

/// PRAGMA incremental_vacuum: gives the file's free pages back to the file system (after a
/// delete; the database is in incremental auto-vacuum mode since migration 5).
void release_free_pages(Database& db);

}  // namespace tessera::server
