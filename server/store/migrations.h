// The store's schema as numbered migrations (Flamenco's habit): each runs once, in its own
// transaction, and is recorded in schema_migrations. Never edit a released migration; add one.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

struct Migration {
  int version;       ///< 1, 2, 3, ... in order, no gaps
  std::string name;  ///< what it does, for people reading schema_migrations
  std::string sql;
  /// Run outside a transaction (VACUUM cannot run inside one), then recorded in its own. Such a
  /// migration must be idempotent: a crash between the two runs it again.
  bool outside_transaction = false;
};

/// Every migration of the schema, in order. docs/farm.md describes the resulting schema.
const std::vector<Migration>& schema_migrations();

/// Applies the migrations `db` lacks, each in a BEGIN IMMEDIATE transaction, and returns the
/// schema version reached. Throws SqliteError; throws std::runtime_error when the database
/// was written by a newer Tessera (a version above every known migration).
/// `up_to` stops after that version (tests build stores as older servers left them).
int migrate(Database& db, int64_t now_unix_ms, int up_to = std::numeric_limits<int>::max());

/// The highest migration applied to `db` (0 for a new database).
int schema_version(Database& db);

/// How many migrations `db` records, without creating anything: a read that fails (SqliteError)
/// when the store cannot answer (the readiness probe).
int64_t migrations_applied(Database& db);

}  // namespace tessera::server
