// Leases on work units: ids, expiry on an injected clock, heartbeats, hand-backs and expiry.
// A lease is current while its unit is 'leased' with that lease_id; every change is a
// compare-and-set on (unit, lease_id, state), so a superseded lease can never change anything.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "clock.h"
#include "job_store.h"
#include "store/sqlite.h"

namespace tessera::server {

struct Lease {
  std::string lease_id;
  int64_t unit_id = 0;
  int64_t job_id = 0;
  uint32_t tile = 0;
  uint32_t batch = 0;
  int64_t worker_id = 0;
  int64_t expires_unix_ms = 0;
};

/// Why a unit is handed back.
enum class ReleaseReason { shutdown, failed };

struct ReleaseOutcome {
  bool released = false;   ///< false: the lease was not current, nothing changed
  bool job_failed = false; ///< the unit failed kUnitFailuresToFailJob times: its job failed
};

/// 128 random bits as 32 lowercase hex characters (std::random_device: the CPU's or the
/// kernel's random source, never a seeded generator).
std::string random_lease_id();

class LeaseTable {
 public:
  /// A worker reporting this many failures on one job gets no more of its units.
  static constexpr int kWorkerFailuresToBlock = 2;
  /// A unit failing this many times (on any workers) fails its job.
  static constexpr int kUnitFailuresToFailJob = 3;

  using IdSource = std::function<std::string()>;

  LeaseTable(Database& db, JobStore& jobs, const Clock& clock, int64_t lease_ms,
             IdSource new_id = random_lease_id);

  int64_t lease_ms() const { return lease_ms_; }

  /// The lease `worker_id` holds, if any (a worker holds at most one).
  std::optional<Lease> held_by(int64_t worker_id);

  /// queued -> leased for `worker_id` with a fresh id, expiring at now + lease_ms. Call inside a
  /// transaction. nullopt when the unit was not queued (someone else won the compare-and-set).
  std::optional<Lease> grant_in_transaction(int64_t unit_id, int64_t worker_id);

  /// Pushes the expiry of a current lease to now + lease_ms. Call inside a transaction.
  /// nullopt when `lease_id` is not the current lease of a unit held by `worker_id`.
  std::optional<int64_t> extend_in_transaction(int64_t worker_id, const std::string& lease_id);

  /// extend_in_transaction in its own transaction.
  std::optional<int64_t> heartbeat(int64_t worker_id, const std::string& lease_id);

  /// leased -> queued. With ReleaseReason::failed the failure counts against the unit (its job
  /// fails with `message` at kUnitFailuresToFailJob) and against the worker on that job.
  ReleaseOutcome release(int64_t worker_id, const std::string& lease_id, ReleaseReason reason,
                         const std::string& message);

  /// Every lease whose expiry is before now -> queued, counted per job (leases_expired) and per
  /// worker (units_lost). Returns how many expired.
  int expire_due();

  /// Every lease -> queued, counted as expired: at server start, leases granted before the
  /// restart are void (their workers may be gone; their results will be dropped as stale).
  int revoke_all();

 private:
  int requeue_where(const std::string& condition, int64_t bound);

  Database& db_;
  JobStore& jobs_;
  const Clock& clock_;
  int64_t lease_ms_;
  IdSource new_id_;
};

}  // namespace tessera::server
