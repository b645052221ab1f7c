#include "farm_store.h"

#include <iostream>
#include <utility>

#include "call_trace.h"
#include "store/integrity.h"
#include "store/migrations.h"
#include "store/quarantine_table.h"
#include "store/workers_table.h"

namespace tessera::server {
namespace {

/// Whether the store needs the whole-file check: only after a server stopped without its clean
/// shutdown, and not for a store this start creates (no migration applied yet: nothing to
/// check). Reads the mark before the migrations run.
bool unclean_start(Database& db, const std::string& db_path) {
  const bool clean = take_clean_shutdown_mark(db, db_path);
  const bool created = schema_version(db) == 0;
  return !clean && !created && db_path != ":memory:";
}

}  // namespace

FarmStore::FarmStore(const std::string& db_path, const Clock& clock, int64_t lease_ms,
                     const WorkerHealthPolicy& health)
    : clock_(clock),
      db_(db_path),
      needs_check_(unclean_start(db_, db_path)),
      jobs_(db_),
      workers_(db_),
      leases_(db_, jobs_, clock_, lease_ms),
      book_(clock_, lease_ms),
      checks_(clock_, lease_ms) {
  migrate(db_, clock_.now_unix_ms());
  checks_.load_quarantines(QuarantineTable(db_).all());
  leases_.set_health_policy(health);
  book_.set_health_policy(health);
  for (int64_t id : jobs_.unfinished()) reload_job(id);
}

void FarmStore::flush_leases() {
  const int64_t began_ns = call_trace::now_ns();
  std::vector<LeaseBook::Grant> grants = book_.take_journal();
  std::map<int64_t, int64_t> touches = book_.take_touches();
  if (grants.empty() && touches.empty()) return;
  struct Traced {
    int64_t began;
    size_t grants;
    ~Traced() { call_trace::record("flush", began, call_trace::now_ns(), int64_t(grants)); }
  } traced{began_ns, grants.size()};
  std::vector<std::optional<int64_t>> unit_ids;
  pins_.learned.clear();
  pins_.refused.clear();
  try {
    Transaction tx(db_);
    unit_ids = write_grants(db_, leases_, grants, &pins_);
    for (const auto& [worker_id, at] : touches) {
      int64_t& written = touched_unix_ms_[worker_id];
      if (at - written < touch_interval_ms()) continue;
      WorkersTable(db_).touch(worker_id, at);  // in this transaction
      written = at;
    }
    tx.commit();
    pins_.known.merge(pins_.learned);
  } catch (...) {
    book_.restore_journal(std::move(grants));
    for (const auto& [worker_id, at] : touches) book_.touch(worker_id, at);
    throw;
  }
  const std::vector<Lease> orphans = book_.recorded(grants, unit_ids);
  if (!orphans.empty()) {
    // Not expected: the book forgot a lease the store took. Back to the queue at once, so that
    // no unit stays leased with nobody to expire it.
    std::cerr << "tessera-server: warning: " << orphans.size()
              << " lease(s) written after the lease book dropped them: requeued" << std::endl;
    for (const Lease& l : leases_.expire(orphans)) reload_job(l.job_id);
  }
  for (int64_t id : std::exchange(pins_.refused, {})) reload_job(id);
}

void FarmStore::reload_job(int64_t job_id) {
  if (std::optional<LeaseBookJob> job = load_lease_book_job(db_, jobs_, job_id)) {
    book_.put_job(std::move(*job));
  } else {
    book_.drop_job(job_id);
  }
}

bool FarmStore::touch_worker(int64_t worker_id, int64_t now_unix_ms) {
  if (const auto it = touched_unix_ms_.find(worker_id);
      it != touched_unix_ms_.end() && now_unix_ms - it->second < touch_interval_ms()) {
    return true;  // seen less than touch_interval_ms() ago: last_seen is recent enough
  }
  if (!workers_.touch(worker_id, now_unix_ms)) return false;
  touched_unix_ms_[worker_id] = now_unix_ms;
  return true;
}

}  // namespace tessera::server
