#include "store/units_table.h"

#include <map>
#include <stdexcept>
#include <utility>

namespace tessera::server {
namespace {

/// A state as an SQL literal: 'leased'.
std::string lit(UnitState state) { return "'" + std::string(to_string(state)) + "'"; }

const std::string kLeasedColumns =
    "id, job_id, tile, batch, worker_id, lease_id, lease_expires_unix_ms";

Lease read_leased(const Statement& q) {
  Lease r;
  r.unit_id = q.int64(0);
  r.job_id = q.int64(1);
  r.tile = uint32_t(q.int64(2));
  r.batch = uint32_t(q.int64(3));
  r.worker_id = q.int64(4);
  r.lease_id = q.text(5);
  r.expires_unix_ms = q.int64(6);
  return r;
}

}  // namespace

std::optional<Lease> UnitsTable::lease(int64_t worker_id, const std::string& lease_id) {
  // By the unique partial index units_lease.
  static const std::string sql = "SELECT " + kLeasedColumns +
                                 " FROM units WHERE lease_id = ?1 AND worker_id = ?2 AND state = " +
                                 lit(UnitState::leased);
  return db_.prepare(sql)->bind_all(lease_id, worker_id).first_row(read_leased);
}

std::vector<Lease> UnitsTable::leases_expiring_before(int64_t bound) {
  static const std::string sql = "SELECT " + kLeasedColumns +
                                 " FROM units INDEXED BY units_expiry WHERE state = " +
                                 lit(UnitState::leased) + " AND lease_expires_unix_ms < ?1";
  return db_.prepare(sql)->bind_all(bound).rows(read_leased);
}

std::vector<LiveUnit> UnitsTable::live(int64_t job_id) {
  std::vector<LiveUnit> out;
  for (const UnitState state : {UnitState::queued, UnitState::leased}) {
    const std::string sql = "SELECT " + kLeasedColumns + " FROM units WHERE job_id = ?1 AND state = " +
                            lit(state) + " ORDER BY batch, tile";
    auto q = db_.prepare(sql);
    q->bind(1, job_id);
    while (q->step()) {
      LiveUnit u;
      u.unit_id = q->int64(0);
      u.tile = uint32_t(q->int64(2));
      u.batch = uint32_t(q->int64(3));
      if (state == UnitState::leased) u.lease = read_leased(*q);
      out.push_back(std::move(u));
    }
  }
  return out;
}

bool UnitsTable::any_queued_or_leased(int64_t job_id) {
  static const std::string sql = "SELECT 1 FROM units WHERE job_id = ?1 AND state IN (" +
                                 lit(UnitState::queued) + ", " + lit(UnitState::leased) +
                                 ") LIMIT 1";
  auto q = db_.prepare(sql);
  q->bind(1, job_id);
  return q->step();
}

std::optional<std::pair<uint32_t, uint32_t>> UnitsTable::tile_batch(int64_t unit_id) {
  return db_.prepare("SELECT tile, batch FROM units WHERE id = ?1")
      ->bind_all(unit_id)
      .first_row([](const Statement& r) {
        return std::pair(uint32_t(r.int64(0)), uint32_t(r.int64(1)));
      });
}

int UnitsTable::lease_requeued(int64_t unit_id, int64_t worker_id, const std::string& lease_id,
                               int64_t expires_unix_ms) {
  static const std::string sql =
      "UPDATE units SET state = " + lit(*next_state(UnitState::queued, UnitEvent::lease)) +
      ", lease_id = ?1, worker_id = ?2, lease_expires_unix_ms = ?3 WHERE id = ?4 AND state = " +
      lit(UnitState::queued);
  db_.prepare(sql)->bind(1, lease_id).bind(2, worker_id).bind(3, expires_unix_ms).bind(4, unit_id)
      .run();
  return db_.changes();
}

int64_t UnitsTable::insert_leased(int64_t job_id, uint32_t tile, uint32_t batch,
                                  int64_t worker_id, const std::string& lease_id,
                                  int64_t expires_unix_ms) {
  // Born leased: the row's first state is the one the lease event leads to from queued.
  static const std::string sql =
      "INSERT INTO units (job_id, tile, batch, state, lease_id, worker_id, lease_expires_unix_ms)"
      " VALUES (?1, ?2, ?3, " + lit(*next_state(UnitState::queued, UnitEvent::lease)) +
      ", ?4, ?5, ?6)";
  db_.prepare(sql)
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, batch)
      .bind(4, lease_id)
      .bind(5, worker_id)
      .bind(6, expires_unix_ms)
      .run();
  return db_.last_insert_rowid();
}

void UnitsTable::insert_cancelled(int64_t job_id, uint32_t tile, uint32_t batch) {
  static const std::string sql =
      "INSERT OR IGNORE INTO units (job_id, tile, batch, state) VALUES (?1, ?2, ?3, " +
      lit(UnitState::cancelled) + ")";
  db_.prepare(sql)->bind(1, job_id).bind(2, tile).bind(3, batch).run();
}

int UnitsTable::accept(int64_t unit_id, int64_t worker_id, const std::string& lease_id) {
  // Unlike end_leases, the row keeps its worker: who delivered the unit.
  static const std::string sql =
      "UPDATE units SET state = " + lit(*next_state(UnitState::leased, UnitEvent::accept)) +
      ", lease_id = NULL, lease_expires_unix_ms = NULL WHERE id = ?1 AND lease_id = ?2"
      " AND worker_id = ?3 AND state = " + lit(UnitState::leased);
  db_.prepare(sql)->bind(1, unit_id).bind(2, lease_id).bind(3, worker_id).run();
  return db_.changes();
}

int64_t UnitsTable::end_leases(UnitEvent event, UnitState from, const std::string& where,
                               const std::function<void(Statement&)>& bind,
                               const std::string& extra_set) {
  const std::optional<UnitState> to = next_state(from, event);
  if (!to) {
    throw std::logic_error("unit event " + std::string(to_string(event)) + " is not allowed in " +
                           std::string(to_string(from)));
  }
  auto q = db_.prepare("UPDATE units SET state = " + lit(*to) +
                       ", lease_id = NULL, worker_id = NULL, lease_expires_unix_ms = NULL" +
                       extra_set + " WHERE state = " + lit(from) + " AND " + where);
  bind(*q);
  q->run();
  return db_.changes();
}

int UnitsTable::requeue(int64_t unit_id, const std::string& lease_id, UnitEvent event,
                        bool failure) {
  return int(end_leases(
      event, UnitState::leased, "id = ?1 AND lease_id = ?2",
      [&](Statement& q) { q.bind(1, unit_id).bind(2, lease_id); },
      failure ? ", failures = failures + 1" : ""));
}

int64_t UnitsTable::skip_tile(int64_t job_id, uint32_t tile) {
  int64_t n = 0;
  for (UnitState from : {UnitState::queued, UnitState::leased}) {
    n += end_leases(UnitEvent::skip, from, "job_id = ?1 AND tile = ?2",
                    [&](Statement& q) { q.bind(1, job_id).bind(2, tile); });
  }
  return n;
}

int64_t UnitsTable::cancel_job(int64_t job_id) {
  int64_t n = 0;
  for (UnitState from : {UnitState::queued, UnitState::leased}) {
    n += end_leases(UnitEvent::cancel, from, "job_id = ?1",
                    [&](Statement& q) { q.bind(1, job_id); });
  }
  return n;
}

int64_t UnitsTable::skip_queued_after_first_batch(int64_t job_id) {
  return end_leases(UnitEvent::skip, UnitState::queued, "job_id = ?1 AND batch > 0",
                    [&](Statement& q) { q.bind(1, job_id); });
}

std::optional<UnitForResult> UnitsTable::for_result(int64_t job_id, uint32_t tile,
                                                    uint32_t batch) {
  auto q = db_.prepare(R"sql(
      SELECT u.id, t.x0, t.y0, t.x1, t.y1, t.next_batch, 0,
             j.width, j.height, j.tile_size, j.spp, j.batch_spp, j.stop_rule, j.noise_target,
             j.batch_schedule, u.state
      FROM units u
      JOIN tiles t ON t.job_id = u.job_id AND t.tile = u.tile
      JOIN jobs j ON j.id = u.job_id
      WHERE u.job_id = ? AND u.tile = ? AND u.batch = ?)sql");
  q->bind(1, job_id).bind(2, tile).bind(3, batch);
  if (!q->step()) return std::nullopt;
  UnitForResult c;
  c.unit_id = q->int64(0);
  c.rect = {int(q->int64(1)), int(q->int64(2)), int(q->int64(3)), int(q->int64(4))};
  c.next_batch = uint32_t(q->int64(5));
  c.plan.width = int(q->int64(7));
  c.plan.height = int(q->int64(8));
  c.plan.tile_size = int(q->int64(9));
  c.plan.spp = uint32_t(q->int64(10));
  c.plan.batch_spp = uint32_t(q->int64(11));
  c.rule = stop_rule_from_string(q->text(12)).value_or(StopRule::spp);
  c.noise_target = q->real(13);
  c.plan.batch_kind = batch_kind_from_string(q->text(14)).value_or(BatchKind::fixed);
  c.cancelled = q->text(15) == to_string(UnitState::cancelled);
  return c;
}

int64_t UnitsTable::count_leased() {
  static const std::string sql =
      "SELECT COUNT(*) FROM units WHERE state = " + lit(UnitState::leased);
  auto q = db_.prepare(sql);
  q->step();
  return q->int64(0);
}

}  // namespace tessera::server
