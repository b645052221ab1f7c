#include "lease_table.h"

#include <limits>
#include <random>
#include <vector>

#include "store/tile_queue.h"

namespace tessera::server {
namespace {

std::string s(UnitState state) { return std::string(to_string(state)); }

}  // namespace

std::string random_lease_id() {
  std::random_device rd;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id;
  for (int i = 0; i < 4; ++i) {
    const uint32_t word = rd();
    for (int k = 0; k < 8; ++k) id.push_back(kHex[(word >> (4 * k)) & 15]);
  }
  return id;
}

LeaseTable::LeaseTable(Database& db, JobStore& jobs, const Clock& clock, int64_t lease_ms,
                       IdSource new_id)
    : db_(db), jobs_(jobs), clock_(clock), lease_ms_(lease_ms), new_id_(std::move(new_id)) {}

std::optional<Lease> LeaseTable::held_by(int64_t worker_id) {
  auto q = db_.prepare(
      "SELECT lease_id, id, job_id, tile, batch, lease_expires_unix_ms FROM units"
      " WHERE worker_id = ? AND state = ? ORDER BY id LIMIT 1");
  q->bind(1, worker_id).bind(2, s(UnitState::leased));
  if (!q->step()) return std::nullopt;
  Lease l;
  l.lease_id = q->text(0);
  l.unit_id = q->int64(1);
  l.job_id = q->int64(2);
  l.tile = uint32_t(q->int64(3));
  l.batch = uint32_t(q->int64(4));
  l.worker_id = worker_id;
  l.expires_unix_ms = q->int64(5);
  return l;
}

std::optional<Lease> LeaseTable::grant_in_transaction(int64_t unit_id, int64_t worker_id) {
  const UnitState to = *next_state(UnitState::queued, UnitEvent::lease);
  const std::string lease_id = new_id_();
  const int64_t expires = clock_.now_unix_ms() + lease_ms_;
  db_.prepare(
         "UPDATE units SET state = ?, lease_id = ?, worker_id = ?, lease_expires_unix_ms = ?"
         " WHERE id = ? AND state = ?")
      ->bind(1, s(to))
      .bind(2, lease_id)
      .bind(3, worker_id)
      .bind(4, expires)
      .bind(5, unit_id)
      .bind(6, s(UnitState::queued))
      .run();
  if (db_.changes() != 1) return std::nullopt;
  return held_by(worker_id);
}

std::optional<Lease> LeaseTable::grant_unborn_in_transaction(int64_t job_id, uint32_t tile,
                                                             uint32_t batch, int64_t worker_id) {
  if (!TileQueue(db_).take(job_id, tile, batch)) return std::nullopt;
  // Born leased: the row's first state is the one the lease event leads to from queued.
  const UnitState to = *next_state(UnitState::queued, UnitEvent::lease);
  db_.prepare(
         "INSERT INTO units (job_id, tile, batch, state, lease_id, worker_id,"
         " lease_expires_unix_ms) VALUES (?, ?, ?, ?, ?, ?, ?)")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, batch)
      .bind(4, s(to))
      .bind(5, new_id_())
      .bind(6, worker_id)
      .bind(7, clock_.now_unix_ms() + lease_ms_)
      .run();
  return held_by(worker_id);
}

std::optional<int64_t> LeaseTable::extend_in_transaction(int64_t worker_id,
                                                         const std::string& lease_id) {
  const int64_t expires = clock_.now_unix_ms() + lease_ms_;
  db_.prepare(
         "UPDATE units SET lease_expires_unix_ms = MAX(lease_expires_unix_ms, ?)"
         " WHERE lease_id = ? AND worker_id = ? AND state = ?")
      ->bind(1, expires)
      .bind(2, lease_id)
      .bind(3, worker_id)
      .bind(4, s(UnitState::leased))
      .run();
  if (db_.changes() != 1) return std::nullopt;
  return expires;
}

std::optional<int64_t> LeaseTable::heartbeat(int64_t worker_id, const std::string& lease_id) {
  Transaction tx(db_);
  const auto expires = extend_in_transaction(worker_id, lease_id);
  tx.commit();
  return expires;
}

ReleaseOutcome LeaseTable::release(int64_t worker_id, const std::string& lease_id,
                                   ReleaseReason reason, const std::string& message) {
  ReleaseOutcome outcome;
  Transaction tx(db_);
  int64_t unit_id = 0, job_id = 0;
  {
    auto q = db_.prepare("SELECT id, job_id FROM units WHERE lease_id = ? AND worker_id = ? AND state = ?");
    q->bind(1, lease_id).bind(2, worker_id).bind(3, s(UnitState::leased));
    if (!q->step()) return outcome;
    unit_id = q->int64(0);
    job_id = q->int64(1);
  }
  const bool failed = reason == ReleaseReason::failed;
  const UnitState to = *next_state(UnitState::leased, UnitEvent::release);
  db_.prepare(
         "UPDATE units SET state = ?, lease_id = NULL, worker_id = NULL,"
         " lease_expires_unix_ms = NULL, failures = failures + ? WHERE id = ? AND lease_id = ?"
         " AND state = ?")
      ->bind(1, s(to))
      .bind(2, failed ? 1 : 0)
      .bind(3, unit_id)
      .bind(4, lease_id)
      .bind(5, s(UnitState::leased))
      .run();
  outcome.released = db_.changes() == 1;
  db_.prepare("UPDATE jobs SET units_released = units_released + 1 WHERE id = ?")
      ->bind(1, job_id)
      .run();
  if (failed) outcome.job_failed = record_failure(unit_id, job_id, worker_id, message);
  tx.commit();
  return outcome;
}

bool LeaseTable::record_failure(int64_t unit_id, int64_t job_id, int64_t worker_id,
                                const std::string& message) {
  const int64_t now = clock_.now_unix_ms();
  // A failure after the forgiveness window starts the worker's count on this job again.
  db_.prepare(
         "INSERT INTO job_worker_failures (job_id, worker_id, failures, last_error,"
         " last_failure_unix_ms) VALUES (?1, ?2, 1, ?3, ?4) ON CONFLICT (job_id, worker_id)"
         " DO UPDATE SET failures = CASE WHEN last_failure_unix_ms <= ?5 THEN 1"
         " ELSE failures + 1 END, last_error = ?3, last_failure_unix_ms = ?4")
      ->bind(1, job_id)
      .bind(2, worker_id)
      .bind(3, message)
      .bind(4, now)
      .bind(5, forgiven_before_unix_ms())
      .run();
  db_.prepare(
         "INSERT INTO unit_failures (unit_id, worker_id, failures, last_error,"
         " last_failure_unix_ms) VALUES (?1, ?2, 1, ?3, ?4) ON CONFLICT (unit_id, worker_id)"
         " DO UPDATE SET failures = failures + 1, last_error = ?3, last_failure_unix_ms = ?4")
      ->bind(1, unit_id)
      .bind(2, worker_id)
      .bind(3, message)
      .bind(4, now)
      .run();
  int64_t workers = 0, attempts = 0;
  std::string reasons;
  {
    auto q = db_.prepare(
        "SELECT f.worker_id, w.name, f.failures, f.last_error FROM unit_failures f"
        " JOIN workers w ON w.id = f.worker_id WHERE f.unit_id = ? ORDER BY f.worker_id");
    q->bind(1, unit_id);
    while (q->step()) {
      ++workers;
      attempts += q->int64(2);
      reasons += std::string(reasons.empty() ? "" : "; ") + "worker " +
                 std::to_string(q->int64(0)) + " (" + q->text(1) + "): " + q->text(3);
    }
  }
  const int64_t max_attempts = int64_t(policy_.workers_to_fail_unit) * policy_.failures_to_block;
  if (workers < policy_.workers_to_fail_unit && attempts < max_attempts) return false;
  uint32_t tile = 0, batch = 0;
  {
    auto q = db_.prepare("SELECT tile, batch FROM units WHERE id = ?");
    q->bind(1, unit_id);
    if (q->step()) {
      tile = uint32_t(q->int64(0));
      batch = uint32_t(q->int64(1));
    }
  }
  return jobs_.fail_in_transaction(job_id,
                                   "unit (tile " + std::to_string(tile) + ", batch " +
                                       std::to_string(batch) + ") failed " +
                                       std::to_string(attempts) + " time(s) on " +
                                       std::to_string(workers) + " worker(s): " + reasons,
                                   now);
}

int LeaseTable::requeue_expiring_before(int64_t bound) {
  struct Expired {
    int64_t unit_id, job_id, worker_id;
    std::string lease_id;
  };
  std::vector<Expired> expired;
  {
    // The literal 'leased' (not a parameter) lets SQLite use the partial indexes on leased
    // units (units_expiry): start-up and expiry read the leased rows alone, not every unit.
    auto q = db_.prepare(
        "SELECT id, job_id, worker_id, lease_id FROM units INDEXED BY units_expiry"
        " WHERE state = 'leased' AND lease_expires_unix_ms < ?1");
    q->bind(1, bound);
    while (q->step()) expired.push_back({q->int64(0), q->int64(1), q->int64(2), q->text(3)});
  }
  const UnitState to = *next_state(UnitState::leased, UnitEvent::expire);
  int count = 0;
  for (const Expired& e : expired) {
    db_.prepare(
           "UPDATE units SET state = ?, lease_id = NULL, worker_id = NULL,"
           " lease_expires_unix_ms = NULL WHERE id = ? AND lease_id = ? AND state = ?")
        ->bind(1, s(to))
        .bind(2, e.unit_id)
        .bind(3, e.lease_id)
        .bind(4, s(UnitState::leased))
        .run();
    if (db_.changes() != 1) continue;
    ++count;
    db_.prepare("UPDATE jobs SET leases_expired = leases_expired + 1 WHERE id = ?")
        ->bind(1, e.job_id)
        .run();
    db_.prepare("UPDATE workers SET units_lost = units_lost + 1 WHERE id = ?")
        ->bind(1, e.worker_id)
        .run();
  }
  return count;
}

int LeaseTable::expire_due() {
  Transaction tx(db_);
  const int count = requeue_expiring_before(clock_.now_unix_ms());
  tx.commit();
  return count;
}

int LeaseTable::revoke_all() {
  Transaction tx(db_);
  const int count = requeue_expiring_before(std::numeric_limits<int64_t>::max());
  tx.commit();
  return count;
}

}  // namespace tessera::server
