#include "store/sqlite.h"

namespace tessera::server {
namespace {

[[noreturn]] void fail(sqlite3* db, int code, std::string_view what) {
  const char* message = db ? sqlite3_errmsg(db) : sqlite3_errstr(code);
  throw SqliteError(code, std::string(what) + ": " + message);
}

void check(sqlite3* db, int code, std::string_view what) {
  if (code != SQLITE_OK) fail(db, code, what);
}

/// Counts a failure for lack of space (any extended code of SQLITE_FULL) before it is thrown.
void note_space_failure(SpaceFailures* full, int code, const std::string& message) {
  if (full && (code & 0xff) == SQLITE_FULL) {
    ++full->count;
    full->last = message;
  }
}

}  // namespace

Statement::Statement(sqlite3* db, std::string_view sql, uint64_t* runs, SpaceFailures* full)
    : db_(db), runs_(runs), full_(full) {
  sqlite3_stmt* raw = nullptr;
  const int rc = sqlite3_prepare_v3(db, sql.data(), int(sql.size()), SQLITE_PREPARE_PERSISTENT,
                                    &raw, nullptr);
  stmt_.reset(raw);
  if (rc != SQLITE_OK) fail(db, rc, "prepare \"" + std::string(sql.substr(0, 60)) + "...\"");
}

Statement& Statement::bind(int index, int64_t value) {
  check(db_, sqlite3_bind_int64(stmt_.get(), index, value), "bind");
  return *this;
}

Statement& Statement::bind(int index, double value) {
  check(db_, sqlite3_bind_double(stmt_.get(), index, value), "bind");
  return *this;
}

Statement& Statement::bind(int index, std::string_view text) {
  check(db_, sqlite3_bind_text64(stmt_.get(), index, text.data(), text.size(), SQLITE_TRANSIENT,
                                 SQLITE_UTF8),
        "bind");
  return *this;
}

Statement& Statement::bind_blob(int index, std::string_view bytes) {
  // A zero-length blob must still be a blob, not NULL: give SQLite a valid pointer.
  static constexpr char kEmpty = 0;
  check(db_,
        sqlite3_bind_blob64(stmt_.get(), index, bytes.empty() ? &kEmpty : bytes.data(),
                            bytes.size(), SQLITE_TRANSIENT),
        "bind");
  return *this;
}

Statement& Statement::bind_blob_borrowed(int index, std::string_view bytes) {
  static constexpr char kEmpty = 0;
  check(db_,
        sqlite3_bind_blob64(stmt_.get(), index, bytes.empty() ? &kEmpty : bytes.data(),
                            bytes.size(), SQLITE_STATIC),
        "bind");
  return *this;
}

Statement& Statement::bind_null(int index) {
  check(db_, sqlite3_bind_null(stmt_.get(), index), "bind");
  return *this;
}

bool Statement::step() {
  if (runs_ && !sqlite3_stmt_busy(stmt_.get())) ++*runs_;
  const int rc = sqlite3_step(stmt_.get());
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  const std::string what =
      "step \"" + std::string(std::string_view(sqlite3_sql(stmt_.get())).substr(0, 60)) + "...\"";
  note_space_failure(full_, rc, what + ": " + sqlite3_errmsg(db_));
  fail(db_, rc, what);
}

void Statement::run() {
  while (step()) {
  }
}

void Statement::reset() {
  sqlite3_reset(stmt_.get());
  sqlite3_clear_bindings(stmt_.get());
}

int Statement::status(int op) const { return sqlite3_stmt_status(stmt_.get(), op, 0); }

int64_t Statement::int64(int column) const { return sqlite3_column_int64(stmt_.get(), column); }

double Statement::real(int column) const { return sqlite3_column_double(stmt_.get(), column); }

std::string Statement::text(int column) const {
  const auto* p = sqlite3_column_text(stmt_.get(), column);
  const int n = sqlite3_column_bytes(stmt_.get(), column);
  return p ? std::string(reinterpret_cast<const char*>(p), size_t(n)) : std::string();
}

std::string Statement::blob(int column) const {
  const void* p = sqlite3_column_blob(stmt_.get(), column);
  const int n = sqlite3_column_bytes(stmt_.get(), column);
  return p ? std::string(static_cast<const char*>(p), size_t(n)) : std::string();
}

bool Statement::is_null(int column) const {
  return sqlite3_column_type(stmt_.get(), column) == SQLITE_NULL;
}

Database::Database(const std::string& path, int busy_timeout_ms) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw,
                                 SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
                                 nullptr);
  db_.reset(raw);
  if (rc != SQLITE_OK) fail(raw, rc, "open " + path);
  sqlite3_extended_result_codes(raw, 1);
  check(raw, sqlite3_busy_timeout(raw, busy_timeout_ms), "busy_timeout");
  // WAL: readers never block the writer; NORMAL sync is durable across process crashes (the
  // farm's failure model: a SIGKILLed server loses nothing committed), fsync at checkpoints.
  exec("PRAGMA journal_mode = WAL");
  exec("PRAGMA synchronous = NORMAL");
  exec("PRAGMA foreign_keys = ON");
  // Accepted results pass through the store (about 19 KB each at 32-px tiles) and most are
  // deleted again at their tile's next checkpoint: a 64 MiB page cache keeps the hot pages
  // (tiles, units, results waiting) from being read back from the file, and 64 MiB of WAL
  // between checkpoints lets a freed page be rewritten in the WAL several times before one
  // copy of it goes to the database file (BENCHMARKS.md, "What a result and a job cost the
  // server, counted": the server no longer read its own pages back, 9-11 % of its CPU).
  exec("PRAGMA cache_size = -65536");
  exec("PRAGMA wal_autocheckpoint = 16384");
  // Debian builds SQLite with SQLITE_SECURE_DELETE, so every deleted row's pages were zeroed
  // and written again: each result dropped at its tile's checkpoint went through the WAL (and
  // the WAL's checkpoint into the file) a second time as zeros, most of the server's I/O per
  // job (BENCHMARKS.md, "What a result and a job cost the server, counted"). FAST still zeroes
  // freed cells on pages a statement writes anyway, but no longer writes a freed page (a deleted
  // result's overflow chain) only to clear it. The store holds renders, not secrets; a deleted
  // job's pages are given back by incremental_vacuum (docs/farm.md, "The store").
  exec("PRAGMA secure_delete = FAST");
}

void Database::exec(std::string_view sql) {
  ++statements_;
  char* error = nullptr;
  const int rc = sqlite3_exec(db_.get(), std::string(sql).c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    const std::string message = error ? error : sqlite3_errstr(rc);
    sqlite3_free(error);
    note_space_failure(&full_, rc, "exec \"" + std::string(sql.substr(0, 60)) + "\": " + message);
    throw SqliteError(rc, "exec: " + message);
  }
}

StatementUse Database::prepare(std::string_view sql) {
  // Looked up by the view: a cached statement costs no std::string (nor its allocation).
  auto it = cache_.find(sql);
  if (it == cache_.end()) {
    it = cache_
             .emplace(std::string(sql),
                      std::make_unique<Statement>(db_.get(), sql, &statements_, &full_))
             .first;
  }
  it->second->reset();
  return StatementUse(*it->second);
}

StoreCounters Database::counters() const {
  StoreCounters c;
  c.statements = statements_;
  for (const auto& [sql, statement] : cache_) {
    c.reprepares += uint64_t(statement->status(SQLITE_STMTSTATUS_REPREPARE));
    c.vm_steps += uint64_t(statement->status(SQLITE_STMTSTATUS_VM_STEP));
  }
  for (const int op : {SQLITE_DBSTATUS_CACHE_HIT, SQLITE_DBSTATUS_CACHE_MISS}) {
    int current = 0, highwater = 0;
    if (sqlite3_db_status(db_.get(), op, &current, &highwater, 0) == SQLITE_OK) {
      c.pages += uint64_t(current);
    }
  }
  return c;
}

int64_t Database::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_.get()); }

int Database::changes() const { return sqlite3_changes(db_.get()); }

Transaction::Transaction(Database& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

Transaction::~Transaction() {
  if (!done_) {
    try {
      db_.exec("ROLLBACK");
    } catch (const SqliteError&) {
      // Nothing more to do: SQLite already rolled back (e.g. after SQLITE_FULL).
    }
  }
}

void Transaction::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

}  // namespace tessera::server
