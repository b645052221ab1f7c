// Start-up and shutdown care of the SQLite store: refuse to serve a damaged database, and leave
// a clean one behind (docs/reliability.md, "Worker health and shutdown").
#pragma once

#include <stdexcept>
#include <string>

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
/// at O(N log N): about 2.6 times its CPU on a 68 MB store (BENCHMARKS.md, "restart").
void check_integrity(Database& db, const std::string& path);

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
