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

/// PRAGMA wal_checkpoint(TRUNCATE): copies the WAL into the database file and empties it, so a
/// stopped server leaves one self-contained file. Returns false when readers kept it busy.
bool checkpoint_wal(Database& db);

}  // namespace tessera::server
