// RAII wrappers over SQLite's C API: a connection, prepared statements, and write transactions.
// Errors are thrown as SqliteError carrying SQLite's (extended) result code, so callers decide
// by code, never by matching message text.
#pragma once

#include <sqlite3.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace tessera::server {

class SqliteError : public std::runtime_error {
 public:
  SqliteError(int code, const std::string& message) : std::runtime_error(message), code_(code) {}
  /// SQLite's extended result code (SQLITE_BUSY, SQLITE_CONSTRAINT_FOREIGNKEY, ...).
  int code() const { return code_; }
  /// The primary result code (extended & 0xff).
  int primary_code() const { return code_ & 0xff; }

 private:
  int code_;
};

/// Writes a connection could not make for lack of space: SQLITE_FULL (a full disk, or the
/// database at its max_page_count). Read by StoreHealth, which tells /readyz, the dashboard and
/// /metrics that the store cannot write.
struct SpaceFailures {
  /// Statements that failed with SQLITE_FULL since the connection opened; atomic so that a
  /// healthy store's status is read without the connection's lock.
  std::atomic<uint64_t> count{0};
  std::string last;  ///< the last one's message, naming the statement (under the lock)
};

/// A prepared statement. Parameters are bound by 1-based index; columns read by 0-based index.
/// Owned by a Database's statement cache (see Database::prepare) or by its creator.
class Statement {
 public:
  /// `runs`, when given, counts each execution (the first step after a reset); `full`, when
  /// given, counts the steps that fail with SQLITE_FULL.
  Statement(sqlite3* db, std::string_view sql, uint64_t* runs = nullptr,
            SpaceFailures* full = nullptr);
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int index, int64_t value);
  Statement& bind(int index, int value) { return bind(index, int64_t(value)); }
  Statement& bind(int index, uint32_t value) { return bind(index, int64_t(value)); }
  Statement& bind(int index, double value);
  /// Text (copied by SQLite).
  Statement& bind(int index, std::string_view text);
  Statement& bind(int index, const char* text) { return bind(index, std::string_view(text)); }
  Statement& bind(int index, const std::string& text) { return bind(index, std::string_view(text)); }
  Statement& bind_blob(int index, std::string_view bytes);
  /// bind_blob without SQLite's copy of the bytes: they must stay alive and unchanged until the
  /// statement has run and its StatementUse is gone (which clears the bindings). For the
  /// `db.prepare(sql)->bind...(bytes).run()` shape with `bytes` owned by the caller (an accepted
  /// result's 19 KB at 32-px tiles: BENCHMARKS.md, "What a result and a job cost the server,
  /// counted").
  Statement& bind_blob_borrowed(int index, std::string_view bytes);
  Statement& bind_null(int index);
  template <typename T>
  Statement& bind(int index, const std::optional<T>& value) {
    return value ? bind(index, *value) : bind_null(index);
  }
  /// Binds `values` to the parameters 1, 2, ... in order.
  template <typename... T>
  Statement& bind_all(const T&... values) {
    int index = 0;
    (bind(++index, values), ...);
    return *this;
  }

  /// The row reader of every query in server/store/: steps through the rows and returns
  /// `read(*this)` of each (`read` takes `const Statement&` and reads the columns it needs).
  /// `db.prepare(sql)->bind_all(a, b).rows(read_x)` is the whole bind-step-read shape.
  template <typename Read>
  auto rows(Read read) -> std::vector<std::invoke_result_t<Read&, const Statement&>> {
    std::vector<std::invoke_result_t<Read&, const Statement&>> out;
    while (step()) out.push_back(read(std::as_const(*this)));
    return out;
  }
  /// The first row as `read(*this)`; nullopt when the query returns none.
  template <typename Read>
  auto first_row(Read read) -> std::optional<std::invoke_result_t<Read&, const Statement&>> {
    if (!step()) return std::nullopt;
    return read(std::as_const(*this));
  }

  /// Advances: true when a row is available, false when done. Throws SqliteError.
  bool step();
  /// Steps a statement that returns no rows (or ignores them) to completion.
  void run();
  /// Clears bindings and rewinds, ready to bind and step again.
  void reset();

  int64_t int64(int column) const;
  double real(int column) const;
  std::string text(int column) const;
  std::string blob(int column) const;
  bool is_null(int column) const;

  /// SQLite's count of `op` (SQLITE_STMTSTATUS_REPREPARE, ..._VM_STEP) for this statement.
  int status(int op) const;

 private:
  struct Finalizer {
    void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
  };
  sqlite3* db_;
  std::unique_ptr<sqlite3_stmt, Finalizer> stmt_;
  uint64_t* runs_;
  SpaceFailures* full_;
};

/// A borrowed cached statement, reset when it goes out of scope so that no half-stepped read
/// keeps a snapshot of the database open. Use as `auto q = db.prepare(sql); q->bind(1, x);`.
class StatementUse {
 public:
  explicit StatementUse(Statement& s) : s_(&s) {}
  StatementUse(StatementUse&& other) noexcept : s_(std::exchange(other.s_, nullptr)) {}
  StatementUse(const StatementUse&) = delete;
  StatementUse& operator=(const StatementUse&) = delete;
  StatementUse& operator=(StatementUse&&) = delete;
  ~StatementUse() {
    if (s_) s_->reset();
  }
  Statement* operator->() const { return s_; }
  Statement& operator*() const { return *s_; }

 private:
  Statement* s_;
};

/// What a connection has executed since it opened: the cost model of the store's operations
/// (BENCHMARKS.md, "What a result and a job cost the server, counted";
/// server/store/store_cost_test.cpp).
struct StoreCounters {
  uint64_t statements = 0;  ///< statements executed, BEGIN and COMMIT included
  /// Cached statements compiled again because a bound value may change their plan (a column
  /// compared with a parameter where a partial index's WHERE names a literal): parsing and
  /// planning each time. The hot paths must keep this at 0.
  uint64_t reprepares = 0;
  /// Virtual-machine steps of the cached statements: proportional to the rows visited, so a
  /// scan shows up where an index walk would not.
  uint64_t vm_steps = 0;
  /// Pages the connection's pager handed out (cache hits and misses, SQLITE_DBSTATUS_CACHE_HIT
  /// and _MISS): every b-tree and overflow page a statement touched, so reading a blob, or
  /// walking past one to a later column of its row, shows up in proportion to its size.
  uint64_t pages = 0;
};

/// One connection. Opened in WAL mode with foreign keys on and a busy timeout. Not thread-safe:
/// the server serialises access (server/coordinator.h).
class Database {
 public:
  /// Opens (creating) `path`; ":memory:" for tests. Throws SqliteError naming the file.
  explicit Database(const std::string& path, int busy_timeout_ms = 5000);
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  /// Runs SQL without parameters (schema, pragmas). Throws SqliteError.
  void exec(std::string_view sql);

  /// A statement prepared once per connection and reused (bindings cleared). Do not hold two
  /// uses of the same SQL text at once.
  StatementUse prepare(std::string_view sql);

  /// Counters since the connection opened.
  StoreCounters counters() const;
  /// The statements (prepared or exec'd) that failed for lack of space since it opened.
  const SpaceFailures& space_failures() const { return full_; }

  int64_t last_insert_rowid() const;
  /// Rows changed by the last INSERT/UPDATE/DELETE.
  int changes() const;

  sqlite3* handle() const { return db_.get(); }

 private:
  struct Closer {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
  };
  std::unique_ptr<sqlite3, Closer> db_;
  std::map<std::string, std::unique_ptr<Statement>, std::less<>> cache_;
  uint64_t statements_ = 0;
  SpaceFailures full_;
};

/// A write transaction: BEGIN IMMEDIATE on construction (takes the write lock at once, so two
/// writers never deadlock upgrading), ROLLBACK on destruction unless commit() was called.
class Transaction {
 public:
  explicit Transaction(Database& db);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  void commit();

 private:
  Database& db_;
  bool done_ = false;
};

}  // namespace tessera::server
