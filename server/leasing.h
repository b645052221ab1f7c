// Work out: leases, answered from the lease book without the store's lock (a long poll waits
// for work to appear), heartbeats that extend them, releases by the worker, and the expiry of
// leases nobody extended (with the time rule: jobs past their budget stop leasing, and those
// with nothing in flight finish).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "farm_events.h"
#include "farm_store.h"
#include "lease_book.h"
#include "lease_table.h"
#include "worker_presence.h"

namespace tessera::server {

/// The samples one LeaseUnit call may lease a worker (docs/farm.md, "Leasing by samples"):
/// about kLeaseSpanMs of its work, so that one worker never holds a large job's units while
/// others idle, and a unit it holds waits at most about that long for its turn.
/// - Measured (WorkerRates): `samples_per_s` x kLeaseSpanMs, the rate being the whole worker's
///   (its units render on all its threads: per render thread, the thread's rate x 1 s).
/// - Not measured yet (a new worker, or any worker after a server start): kUnmeasuredSamples
///   per render thread, the figure tessera-worker asks by (a few tens of milliseconds of work
///   per thread): a batch of small units still travels in one call, a large unit alone.
/// The call still returns at least one unit when there is work (LeaseBook::lease_up_to).
inline constexpr int64_t kLeaseSpanMs = 1000;
inline constexpr uint64_t kUnmeasuredSamples = uint64_t(1) << 16;
uint64_t lease_sample_budget(const WorkerRates::Rate& rate);

class Leasing {
 public:
  /// Called, outside the store's lock, for each job whose time is up (JobImages::finish_job).
  using FinishJob = std::function<void(int64_t job_id)>;

  Leasing(FarmStore& store, WorkerPresence& presence, FarmEvents& events, const Clock& clock,
          FinishJob finish_job)
      : store_(store),
        presence_(presence),
        events_(events),
        clock_(clock),
        finish_job_(std::move(finish_job)) {}

  /// Most leases a worker may name as delivering in one LeaseUnit call.
  static constexpr size_t kMaxDelivering = 64;
  /// Most lease ids one heartbeat may name.
  static constexpr size_t kMaxLeasesPerHeartbeat = 64;

  /// Every lease the worker holds and new ones up to `max_units` and the worker's sample
  /// budget (lease_sample_budget; LeaseBook::lease_up_to), waiting up to `wait` while there
  /// are none (long poll) unless `cancelled()` says the caller went away. Empty: no work. `delivering`: leases whose results the worker is delivering,
  /// left out (at most kMaxDelivering; more throws FarmError(invalid_argument)). Throws
  /// FarmError(failed_precondition) for an unknown worker id (register again).
  std::vector<LeasedUnit> lease_units(int64_t worker_id, uint32_t max_units,
                                      std::chrono::milliseconds wait,
                                      const std::function<bool()>& cancelled,
                                      const std::vector<std::string>& delivering);
  /// heartbeat() of several leases in one call; answer i is lease i's: the new expiry, or
  /// nullopt when the lease is not current. Throws FarmError(invalid_argument) for more than
  /// kMaxLeasesPerHeartbeat.
  std::vector<std::optional<int64_t>> heartbeat_all(int64_t worker_id,
                                                    const std::vector<std::string>& lease_ids);
  std::optional<int64_t> heartbeat(int64_t worker_id, const std::string& lease_id);
  ReleaseOutcome release(int64_t worker_id, const std::string& lease_id, ReleaseReason reason,
                         const std::string& message);
  /// Returns expired leases' units to the queue and applies the time rule; called by the
  /// LeaseReaper. Returns how many expired.
  int expire_leases();

 private:
  /// One look for work: nothing for a quarantined worker, else the book's leases with a spot
  /// check the worker may render first (server/spot_checks.h).
  std::vector<LeasedUnit> lease_with_checks(int64_t worker_id, uint32_t max_units,
                                            const std::vector<std::string>& delivering,
                                            uint64_t budget);
  /// A lease's heartbeat: the book's lease, or else a spot check's.
  std::optional<int64_t> extend(int64_t worker_id, const std::string& lease_id);

  FarmStore& store_;
  WorkerPresence& presence_;
  FarmEvents& events_;
  const Clock& clock_;
  FinishJob finish_job_;
};

}  // namespace tessera::server
