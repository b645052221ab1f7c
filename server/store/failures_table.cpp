#include "store/failures_table.h"

namespace tessera::server {

void FailuresTable::record(int64_t job_id, int64_t unit_id, int64_t worker_id,
                           const std::string& message, int64_t now, int64_t forgiven_before) {
  db_.prepare(
         "INSERT INTO job_worker_failures (job_id, worker_id, failures, last_error,"
         " last_failure_unix_ms) VALUES (?1, ?2, 1, ?3, ?4) ON CONFLICT (job_id, worker_id)"
         " DO UPDATE SET failures = CASE WHEN last_failure_unix_ms <= ?5 THEN 1"
         " ELSE failures + 1 END, last_error = ?3, last_failure_unix_ms = ?4")
      ->bind(1, job_id)
      .bind(2, worker_id)
      .bind(3, message)
      .bind(4, now)
      .bind(5, forgiven_before)
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
}

std::vector<UnitFailure> FailuresTable::of_unit(int64_t unit_id) {
  return db_
      .prepare(
          "SELECT f.worker_id, w.name, f.failures, f.last_error FROM unit_failures f"
          " JOIN workers w ON w.id = f.worker_id WHERE f.unit_id = ? ORDER BY f.worker_id")
      ->bind_all(unit_id)
      .rows([](const Statement& r) {
        return UnitFailure{r.int64(0), r.text(1), r.int64(2), r.text(3)};
      });
}

std::vector<JobWorkerFailures> FailuresTable::of_job(int64_t job_id) {
  return db_
      .prepare("SELECT worker_id, failures, last_failure_unix_ms FROM job_worker_failures"
               " WHERE job_id = ?")
      ->bind_all(job_id)
      .rows([](const Statement& r) {
        return JobWorkerFailures{r.int64(0), r.int64(1), r.int64(2)};
      });
}

}  // namespace tessera::server
