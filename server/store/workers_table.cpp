#include "store/workers_table.h"

namespace tessera::server {
namespace {

constexpr const char* kSelect = R"sql(
  SELECT w.id, w.name, w.threads, w.isa, w.version, w.registered_unix_ms, w.last_seen_unix_ms,
         w.units_done, w.units_lost, u.job_id, u.tile, u.batch, w.samples_returned,
         w.nan_dropped, w.inf_dropped
  FROM workers w LEFT JOIN units u ON u.id = (
    SELECT l.id FROM units l WHERE l.worker_id = w.id AND l.state = 'leased' ORDER BY l.id LIMIT 1)
)sql";

WorkerRecord read_worker(const Statement& q) {
  WorkerRecord w;
  w.id = q.int64(0);
  w.info.name = q.text(1);
  w.info.threads = uint32_t(q.int64(2));
  w.info.isa = q.text(3);
  w.info.version = q.text(4);
  w.registered_unix_ms = q.int64(5);
  w.last_seen_unix_ms = q.int64(6);
  w.units_done = uint64_t(q.int64(7));
  w.units_lost = uint64_t(q.int64(8));
  w.samples_returned = uint64_t(q.int64(12));
  w.nan_dropped = uint64_t(q.int64(13));
  w.inf_dropped = uint64_t(q.int64(14));
  if (!q.is_null(9)) {
    w.job_id = q.int64(9);
    w.tile = uint32_t(q.int64(10));
    w.batch = uint32_t(q.int64(11));
  }
  return w;
}

}  // namespace

int64_t WorkersTable::insert(const WorkerRegistration& info, int64_t now) {
  db_.prepare(
         "INSERT INTO workers (name, threads, isa, version, registered_unix_ms,"
         " last_seen_unix_ms) VALUES (?, ?, ?, ?, ?, ?)")
      ->bind(1, info.name)
      .bind(2, info.threads)
      .bind(3, info.isa)
      .bind(4, info.version)
      .bind(5, now)
      .bind(6, now)
      .run();
  return db_.last_insert_rowid();
}

bool WorkersTable::touch(int64_t worker_id, int64_t now) {
  db_.prepare("UPDATE workers SET last_seen_unix_ms = MAX(last_seen_unix_ms, ?) WHERE id = ?")
      ->bind(1, now)
      .bind(2, worker_id)
      .run();
  return db_.changes() == 1;
}

void WorkersTable::count_delivered(int64_t worker_id, uint64_t units, uint64_t samples,
                                   uint64_t nan, uint64_t inf) {
  db_.prepare(
         "UPDATE workers SET units_done = units_done + ?, samples_returned = samples_returned + ?,"
         " nan_dropped = nan_dropped + ?, inf_dropped = inf_dropped + ? WHERE id = ?")
      ->bind(1, int64_t(units))
      .bind(2, int64_t(samples))
      .bind(3, int64_t(nan))
      .bind(4, int64_t(inf))
      .bind(5, worker_id)
      .run();
}

void WorkersTable::count_lost(int64_t worker_id) {
  db_.prepare("UPDATE workers SET units_lost = units_lost + 1 WHERE id = ?")
      ->bind(1, worker_id)
      .run();
}

std::optional<WorkerRecord> WorkersTable::get(int64_t worker_id) {
  return db_.prepare(std::string(kSelect) + " WHERE w.id = ?1")
      ->bind_all(worker_id)
      .first_row(read_worker);
}

std::vector<WorkerRecord> WorkersTable::list() {
  return db_.prepare(std::string(kSelect) + " ORDER BY w.last_seen_unix_ms DESC, w.id DESC")
      ->rows(read_worker);
}

int64_t WorkersTable::count() {
  auto q = db_.prepare("SELECT COUNT(*) FROM workers");
  q->step();
  return q->int64(0);
}

}  // namespace tessera::server
