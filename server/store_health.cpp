#include "store_health.h"

#include <chrono>
#include <iostream>

#include "store/migrations.h"

namespace tessera::server {

StoreHealth::StoreHealth(FarmStore& store, FarmEvents& events, const std::string& db_path)
    : store_(store), events_(events) {
  // The whole-file check only after a server stopped without its clean shutdown (a crash, a
  // kill): a clean restart reads no page beyond the header, whatever the store's size. It runs
  // beside the server, not before it: SQLite recovers from a process crash by itself (WAL), and
  // the check, which reads the whole file (tens of seconds on a store of hundreds of MB), guards
  // against a damaged disk or file, which it reports when it finds it.
  if (!store.needs_check()) return;
  std::cerr << "tessera-server: " << db_path
            << " was not closed by a clean shutdown: checking it (PRAGMA quick_check) in the"
               " background while serving"
            << std::endl;
  const auto began = std::chrono::steady_clock::now();
  check_ = std::make_unique<BackgroundIntegrityCheck>(
      db_path, [this, began, path = db_path](IntegrityState state, const std::string& message) {
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
        if (state == IntegrityState::damaged) {
          damaged(message);
        } else if (state == IntegrityState::ok) {
          std::cerr << "tessera-server: " << path << ": check passed (" << s << " s)" << std::endl;
        } else if (!message.empty()) {
          std::cerr << "tessera-server: warning: " << path << ": " << message
                    << " (the next start checks again)" << std::endl;
        }
      });
}

bool StoreHealth::checkpoint() {
  // A check that ends early (or found damage) leaves no mark: the next start checks again.
  bool checked = true;
  if (check_) {
    check_->stop();
    checked = check_->state() == IntegrityState::ok;
  }
  FarmStore::Lock lock(store_);
  if (checked) leave_clean_shutdown_mark(store_.db());
  return checkpoint_wal(store_.db());
}

void StoreHealth::damaged(const std::string& message) {
  std::cerr << "tessera-server: ERROR: " << message
            << "; no more leases (uploads of leased units still commit); stop the server"
            << std::endl;
  events_.stop();  // LeaseUnit answers "no work", long polls and watches end, /readyz fails
  std::lock_guard lock(damage_mu_);  // held while the observer runs: see set_damage_observer
  damage_ = message;
  if (damage_observer_) damage_observer_(message);
}

std::optional<IntegrityState> StoreHealth::check() const {
  if (!check_) return std::nullopt;
  return check_->state();
}

std::optional<double> StoreHealth::check_progress() const {
  if (!check_) return std::nullopt;
  return check_->progress();
}

std::optional<IntegrityState> StoreHealth::wait_for_check() const {
  if (!check_) return std::nullopt;
  return check_->wait();
}

std::string StoreHealth::damage() const {
  std::lock_guard lock(damage_mu_);
  return damage_;
}

void StoreHealth::set_damage_observer(std::function<void(const std::string&)> observer) {
  std::lock_guard lock(damage_mu_);
  damage_observer_ = std::move(observer);
  if (!damage_.empty() && damage_observer_) damage_observer_(damage_);
}

std::string StoreHealth::unready_reason() {
  if (const std::string d = damage(); !d.empty()) return "the store is damaged: " + d;
  try {
    FarmStore::Lock lock(store_);  // the lease journal written, as every write would
    migrations_applied(store_.db());
  } catch (const SqliteError& e) {
    // No space for the journal: write_error says so below.
    if (e.primary_code() != SQLITE_FULL) {
      return std::string("the store does not answer: ") + e.what();
    }
  }
  if (const std::string w = write_error(); !w.empty()) return "the store cannot write: " + w;
  return "";
}

std::string StoreHealth::write_error() {
  {
    std::lock_guard guard(write_mu_);
    if (write_error_.empty() && store_.db().space_failures().count == space_failures_seen_) {
      return "";
    }
  }
  FarmStore::ReadLock lock(store_);
  std::lock_guard guard(write_mu_);
  const int64_t now = store_.clock().now_unix_ms();
  const SpaceFailures& failures = store_.db().space_failures();
  if (failures.count != space_failures_seen_) {
    space_failures_seen_ = failures.count;
    probed_unix_ms_ = now;
    if (write_error_.empty()) {
      std::cerr << "tessera-server: ERROR: the store cannot write (" << failures.last
                << "): uploads and submissions fail until there is space; reads go on, /readyz"
                   " answers 503"
                << std::endl;
    }
    write_error_ = failures.last;
  } else if (!write_error_.empty() && now - probed_unix_ms_ >= kProbeIntervalMs) {
    probed_unix_ms_ = now;
    const bool wrote = probe_write();
    space_failures_seen_ = store_.db().space_failures().count;  // the probe's own failures
    if (wrote) {
      write_error_.clear();
      std::cerr << "tessera-server: the store writes again" << std::endl;
    }
  }
  return write_error_;
}

bool StoreHealth::probe_write() {
  Database& db = store_.db();
  try {
    {
      Transaction tx(db);
      db.exec("CREATE TABLE IF NOT EXISTS store_write_probe (bytes BLOB NOT NULL)");
      db.exec("INSERT INTO store_write_probe VALUES (zeroblob(" + std::to_string(kProbeBytes) +
              "))");
      tx.commit();
    }
    Transaction tx(db);
    db.exec("DROP TABLE store_write_probe");
    tx.commit();
    return true;
  } catch (const SqliteError&) {
    return false;
  }
}

}  // namespace tessera::server
