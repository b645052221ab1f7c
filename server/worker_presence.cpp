#include "worker_presence.h"

#include <iostream>
#include <string>

#include "call_trace.h"
#include "farm_error.h"

namespace tessera::server {
namespace {

FarmError unknown_worker(int64_t worker_id) {
  // FAILED_PRECONDITION, not NOT_FOUND: the worker tells "register again" by the code alone.
  return FarmError(ErrorCode::failed_precondition,
                   "no worker " + std::to_string(worker_id) + ": register again");
}

}  // namespace

int64_t WorkerPresence::register_worker(const WorkerRegistration& info) {
  int64_t id = 0;
  {
    FarmStore::Lock lock(store_);
    id = store_.workers().register_worker(info, clock_.now_unix_ms());
    store_.book().add_worker(id, info.version);
    store_.checks().add_worker(id, info.name, info.version);
    rates_.set_threads(id, info.threads);
  }
  events_.notify(true);
  return id;
}

void WorkerPresence::deregister(int64_t worker_id) {
  std::lock_guard lock(departed_mu_);
  departed_[worker_id] = calls_begun_.load();
}

bool WorkerPresence::online(const WorkerRecord& worker) const {
  {
    std::lock_guard lock(departed_mu_);
    if (departed_.contains(worker.id)) return false;
  }
  return clock_.now_unix_ms() - worker.last_seen_unix_ms <= 3 * store_.lease_ms();
}

std::vector<WorkerRecord> WorkerPresence::workers() {
  FarmStore::ReadLock lock(store_);
  std::vector<WorkerRecord> list = store_.workers().list();
  const std::map<int64_t, size_t> held = store_.book().held_by_worker();
  for (WorkerRecord& w : list) {
    w.health_warning = health_warning(w, nan_report_fraction_);
    if (const auto h = held.find(w.id); h != held.end()) w.units_held = uint32_t(h->second);
    w.quarantine = store_.checks().quarantine_of(w.id);
    const CheckCounts counts = store_.checks().counts_of_worker(w.id);
    w.checks = counts.checked;
    w.mismatches = counts.mismatches;
  }
  return list;
}

void WorkerPresence::came_back(int64_t worker_id, uint64_t call) {
  std::lock_guard lock(departed_mu_);
  // A call begun after it deregistered: it calls again, online again. A long poll begun before
  // (its worker stopped while it waited) does not count.
  if (const auto it = departed_.find(worker_id); it != departed_.end() && call >= it->second) {
    departed_.erase(it);
  }
}

void WorkerPresence::touch_in_memory(int64_t worker_id, uint64_t call) {
  const int64_t began_ns = call_trace::now_ns();
  came_back(worker_id, call);
  LeaseBook& book = store_.book();
  if (!book.knows_worker(worker_id)) {
    // Its first call since the server started (or an unknown id): the one lease or heartbeat
    // of a worker that asks the store.
    FarmStore::Lock lock(store_);
    const std::optional<WorkerRecord> known = store_.workers().get(worker_id);
    if (!known) throw unknown_worker(worker_id);
    book.add_worker(worker_id, known->info.version);
    store_.checks().add_worker(worker_id, known->info.name, known->info.version);
    rates_.set_threads(worker_id, known->info.threads);
  }
  const int64_t now = clock_.now_unix_ms();
  book.touch(worker_id, now);  // last_seen written by the next flush
  store_.checks().seen(worker_id, now);  // online for spot checks
  call_trace::record("touch", began_ns, call_trace::now_ns());
}

void WorkerPresence::touch_or_throw(int64_t worker_id, uint64_t call) {
  came_back(worker_id, call);
  if (!store_.touch_worker(worker_id, clock_.now_unix_ms())) throw unknown_worker(worker_id);
}

void WorkerPresence::report_health(int64_t worker_id) {
  std::lock_guard lock(reported_mu_);
  if (reported_workers_.contains(worker_id)) return;
  const std::optional<WorkerRecord> w = store_.workers().get(worker_id);
  if (!w) return;
  const std::string warning = health_warning(*w, nan_report_fraction_);
  if (warning.empty()) return;
  reported_workers_.insert(worker_id);
  std::cerr << "tessera-server: warning: worker " << worker_id << " (" << w->info.name
            << "): " << warning << std::endl;
}

}  // namespace tessera::server
