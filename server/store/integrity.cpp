#include "store/integrity.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace tessera::server {

std::string corrupt_store_message(const std::string& path, const std::string& detail) {
  return "database " + path + " is damaged (" + detail +
         "); refusing to serve it: restore a backup, or move the file away to start empty";
}

bool is_corruption(const SqliteError& e) {
  return e.primary_code() == SQLITE_CORRUPT || e.primary_code() == SQLITE_NOTADB;
}

void check_integrity(Database& db, const std::string& path) {
  std::vector<std::string> problems;
  try {
    auto q = db.prepare("PRAGMA quick_check(10)");
    while (q->step()) {
      std::string row = q->text(0);
      if (row != "ok") problems.push_back(std::move(row));
    }
  } catch (const SqliteError& e) {
    if (is_corruption(e)) throw StoreCorrupt(corrupt_store_message(path, e.what()));
    throw;
  }
  if (problems.empty()) return;
  std::string detail = "PRAGMA quick_check: " + problems.front();
  if (problems.size() > 1) detail += " (and " + std::to_string(problems.size() - 1) + " more)";
  for (char& c : detail) c = c == '\n' ? ' ' : c;
  throw StoreCorrupt(corrupt_store_message(path, detail));
}

const char* integrity_state_name(IntegrityState state) {
  switch (state) {
    case IntegrityState::checking: return "checking";
    case IntegrityState::ok: return "ok";
    case IntegrityState::damaged: return "damaged";
    case IntegrityState::interrupted: return "interrupted";
  }
  return "unknown";
}

BackgroundIntegrityCheck::BackgroundIntegrityCheck(std::string path, EndCallback on_end)
    : path_(std::move(path)), on_end_(std::move(on_end)), thread_([this] { run(); }) {}

BackgroundIntegrityCheck::~BackgroundIntegrityCheck() { stop(); }

IntegrityState BackgroundIntegrityCheck::state() const {
  std::lock_guard lock(mu_);
  return state_;
}

std::string BackgroundIntegrityCheck::message() const {
  std::lock_guard lock(mu_);
  return message_;
}

double BackgroundIntegrityCheck::progress() const {
  if (state() == IntegrityState::ok) return 1.0;
  const int64_t total = pages_total_.load();
  if (total <= 0) return 0.0;
  return std::min(1.0, double(pages_read_.load()) / double(total));
}

IntegrityState BackgroundIntegrityCheck::wait() const {
  std::unique_lock lock(mu_);
  ended_.wait(lock, [&] { return state_ != IntegrityState::checking; });
  return state_;
}

void BackgroundIntegrityCheck::stop() {
  {
    std::unique_lock lock(mu_);
    stop_requested_ = true;
    // An interrupt that lands between two statements is forgotten by SQLite: repeat it until the
    // check has ended.
    while (state_ == IntegrityState::checking) {
      if (db_) sqlite3_interrupt(db_->handle());
      ended_.wait_for(lock, std::chrono::milliseconds(20));
    }
  }
  if (thread_.joinable()) thread_.join();
}

void BackgroundIntegrityCheck::finish(IntegrityState state, std::string message) {
  {
    std::lock_guard lock(mu_);
    // After a stop request nothing the check says counts: an interrupted quick_check may
    // report the pages it did not reach as "never used".
    if (stop_requested_ && state != IntegrityState::ok) {
      state = IntegrityState::interrupted;
      message.clear();
    }
  }
  // Before the state is published, so that whoever wait()s sees what the callback did.
  if (on_end_) on_end_(state, message);
  {
    std::lock_guard lock(mu_);
    state_ = state;
    message_ = std::move(message);
  }
  ended_.notify_all();
}

void BackgroundIntegrityCheck::run() {
  IntegrityState state = IntegrityState::ok;
  std::string message;
  try {
    Database db(path_);
    db.exec("PRAGMA query_only = 1");    // a reader: it can never write the store
    db.exec("PRAGMA cache_size = -8192");  // it reads each page once: 8 MiB is plenty
    {
      auto q = db.prepare("PRAGMA page_count");
      if (q->step()) pages_total_ = q->int64(0);
    }
    // Progress (progress()): SQLite calls the handler on the check's own thread, between VM
    // steps, so the connection's counters are read where they are written.
    struct Probe {
      sqlite3* db;
      std::atomic<int64_t>* pages_read;
    } probe{db.handle(), &pages_read_};
    sqlite3_progress_handler(
        db.handle(), 4096,
        [](void* arg) {
          const auto* p = static_cast<const Probe*>(arg);
          int misses = 0, highwater = 0;
          sqlite3_db_status(p->db, SQLITE_DBSTATUS_CACHE_MISS, &misses, &highwater, 0);
          p->pages_read->store(misses);
          return 0;  // go on
        },
        &probe);
    {
      std::lock_guard lock(mu_);
      if (stop_requested_) {
        state = IntegrityState::interrupted;
      } else {
        db_ = &db;
      }
    }
    if (state != IntegrityState::interrupted) {
      try {
        check_integrity(db, path_);
      } catch (const StoreCorrupt& e) {
        state = IntegrityState::damaged;
        message = e.what();
      } catch (const SqliteError& e) {
        state = IntegrityState::interrupted;
        if (e.primary_code() != SQLITE_INTERRUPT) message = std::string("check failed: ") + e.what();
      }
      std::lock_guard lock(mu_);
      db_ = nullptr;
    }
  } catch (const SqliteError& e) {
    // Opening the second connection failed (the server's own open succeeded a moment ago).
    if (is_corruption(e)) {
      state = IntegrityState::damaged;
      message = corrupt_store_message(path_, e.what());
    } else {
      state = IntegrityState::interrupted;
      message = std::string("check failed: ") + e.what();
    }
  }
  finish(state, std::move(message));
}

namespace {

/// PRAGMA user_version while no server has the store open since a clean shutdown. Any other
/// value (0 for every store before the mark, and while a server runs) means "check it".
constexpr int64_t kCleanShutdownMark = 0x7e55e7a;

}  // namespace

bool take_clean_shutdown_mark(Database& db, const std::string& path) {
  try {
    bool clean = false;
    {
      auto q = db.prepare("PRAGMA user_version");
      clean = q->step() && q->int64(0) == kCleanShutdownMark;
    }
    if (clean) db.exec("PRAGMA user_version = 0");
    return clean;
  } catch (const SqliteError& e) {
    if (is_corruption(e)) throw StoreCorrupt(corrupt_store_message(path, e.what()));
    throw;
  }
}

void leave_clean_shutdown_mark(Database& db) {
  db.exec("PRAGMA user_version = " + std::to_string(kCleanShutdownMark));
}

bool checkpoint_wal(Database& db) {
  auto q = db.prepare("PRAGMA wal_checkpoint(TRUNCATE)");
  if (!q->step()) return false;
  return q->int64(0) ==
         0;  // column 0: 1 when a reader or writer kept the checkpoint from completing
}

void release_free_pages(Database& db) { db.exec("PRAGMA incremental_vacuum"); }

}  // namespace tessera::server
