// Which workers are there: registration, the check of a worker's id on each of its calls (its
// last call recorded), deregistration, whether a worker is online, how fast each renders (its
// measured rate, which bounds its leases), and the one-time warning for a worker whose NaN/Inf
// share crossed the report threshold. A lease's or heartbeat's
// check is answered from memory (the lease book's known workers); the store is asked only for
// a worker new to this server.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include "clock.h"
#include "farm_events.h"
#include "farm_store.h"
#include "worker_rates.h"
#include "worker_registry.h"

namespace tessera::server {

class WorkerPresence {
 public:
  /// `nan_report_fraction`: a worker whose NaN/Inf samples exceed this fraction of its samples
  /// is reported.
  WorkerPresence(FarmStore& store, FarmEvents& events, const Clock& clock,
                 double nan_report_fraction)
      : store_(store), events_(events), clock_(clock), nan_report_fraction_(nan_report_fraction) {}

  int64_t register_worker(const WorkerRegistration& info);
  /// The worker is stopping: online() is false for it until it calls again. Kept in memory
  /// (after a server restart a departed worker is offline three lease periods after its last
  /// call, as one that vanished).
  void deregister(int64_t worker_id);
  /// True when the worker called within the last three lease periods and did not deregister
  /// since.
  bool online(const WorkerRecord& worker) const;
  /// Every worker, with its health warning and the units it holds now (the lease book's).
  std::vector<WorkerRecord> workers();
  /// Each worker's render threads and measured rate (results record into it: ResultIntake).
  WorkerRates& rates() { return rates_; }

  /// The number of a call, taken when the call begins: a call that began before its worker
  /// deregistered (a long poll still waiting) does not bring it back online.
  uint64_t begin_call() { return calls_begun_.fetch_add(1); }
  /// A lease's, heartbeat's or upload's check of the worker, in memory: its departure
  /// forgotten, its last call recorded in the lease book (written to the store by the next
  /// flush). Takes the store's lock only for a worker new to this server; throws
  /// FarmError(failed_precondition) for an unknown one (register again).
  void touch_in_memory(int64_t worker_id, uint64_t call);
  /// The same check against the store, for calls that hold the store's lock (a release).
  void touch_or_throw(int64_t worker_id, uint64_t call);
  /// Logs, once per server run, a worker whose NaN/Inf share crossed the report threshold.
  /// Requires the store's lock.
  void report_health(int64_t worker_id);

 private:
  /// Forgets the worker's departure when `call` began after it.
  void came_back(int64_t worker_id, uint64_t call);

  FarmStore& store_;
  FarmEvents& events_;
  const Clock& clock_;
  const double nan_report_fraction_;
  mutable std::mutex departed_mu_;
  /// Workers that deregistered and have not called since: worker id -> the number of calls
  /// begun when it deregistered (calls numbered from there on began after it).
  std::map<int64_t, uint64_t> departed_;
  std::atomic<uint64_t> calls_begun_{0};
  WorkerRates rates_;
  std::mutex reported_mu_;
  std::set<int64_t> reported_workers_;  ///< NaN/Inf warning logged (guarded by reported_mu_)
};

}  // namespace tessera::server
