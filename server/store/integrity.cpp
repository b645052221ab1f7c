#include "store/integrity.h"

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
