#include "worker_registry.h"

#include <cstdio>

#include "job_state.h"

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

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g%%", 100.0 * fraction);
  return text;
}

}  // namespace

std::string health_warning(const WorkerRecord& worker, double report_fraction) {
  if (worker.samples_returned < kMinSamplesToJudge || worker.samples_returned == 0) return {};
  const uint64_t bad = worker.nan_dropped + worker.inf_dropped;
  const double fraction = double(bad) / double(worker.samples_returned);
  if (fraction <= report_fraction) return {};
  return percent(fraction) + " of its samples were NaN/Inf (" + std::to_string(worker.nan_dropped) +
         " NaN, " + std::to_string(worker.inf_dropped) + " Inf; report threshold " +
         percent(report_fraction) + ")";
}

int64_t WorkerRegistry::register_worker(const WorkerRegistration& info, int64_t now) {
  Transaction tx(db_);
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
  const int64_t id = db_.last_insert_rowid();
  tx.commit();
  return id;
}

bool WorkerRegistry::touch(int64_t worker_id, int64_t now) {
  Transaction tx(db_);
  db_.prepare("UPDATE workers SET last_seen_unix_ms = MAX(last_seen_unix_ms, ?) WHERE id = ?")
      ->bind(1, now)
      .bind(2, worker_id)
      .run();
  const bool found = db_.changes() == 1;
  tx.commit();
  return found;
}

std::optional<WorkerRecord> WorkerRegistry::get(int64_t worker_id) {
  auto q = db_.prepare(std::string(kSelect) + " WHERE w.id = ?1");
  q->bind(1, worker_id);
  if (!q->step()) return std::nullopt;
  return read_worker(*q);
}

std::vector<WorkerRecord> WorkerRegistry::list() {
  std::vector<WorkerRecord> out;
  auto q = db_.prepare(std::string(kSelect) + " ORDER BY w.last_seen_unix_ms DESC, w.id DESC");
  while (q->step()) out.push_back(read_worker(*q));
  return out;
}

}  // namespace tessera::server
