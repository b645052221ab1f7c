#include "store/results_table.h"

namespace tessera::server {

void ResultsTable::append(int64_t job_id, uint32_t tile, uint32_t batch,
                          const std::string& encoded) {
  db_.prepare("INSERT INTO results (job_id, tile, batch, accumulation) VALUES (?, ?, ?, ?)")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, batch)
      .bind_blob_borrowed(4, encoded)  // `encoded` outlives the run
      .run();
}

std::optional<std::string> ResultsTable::find(int64_t job_id, uint32_t tile, uint32_t batch) {
  auto q = db_.prepare(
      "SELECT accumulation FROM results WHERE job_id = ? AND tile = ? AND batch = ?");
  return q->bind_all(job_id, tile, batch).first_row([](const Statement& r) { return r.blob(0); });
}

uint32_t ResultsTable::first_merged(int64_t job_id, uint32_t tile, uint32_t next_batch) {
  auto q = db_.prepare(
      "SELECT MIN(batch) FROM results WHERE job_id = ? AND tile = ? AND batch < ?");
  q->bind(1, job_id).bind(2, tile).bind(3, next_batch);
  if (q->step() && !q->is_null(0)) return uint32_t(q->int64(0));
  return next_batch;
}

void ResultsTable::for_each_merged(int64_t job_id, uint32_t tile, uint32_t next_batch,
                                   const std::function<void(uint32_t, const std::string&)>& each) {
  auto q = db_.prepare(
      "SELECT batch, accumulation FROM results WHERE job_id = ? AND tile = ? AND batch < ?"
      " ORDER BY batch");
  q->bind(1, job_id).bind(2, tile).bind(3, next_batch);
  while (q->step()) each(uint32_t(q->int64(0)), q->blob(1));
}

int64_t ResultsTable::drop_merged(int64_t job_id, uint32_t tile, uint32_t next_batch) {
  db_.prepare("DELETE FROM results WHERE job_id = ? AND tile = ? AND batch < ?")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, next_batch)
      .run();
  return db_.changes();
}

int64_t ResultsTable::drop_waiting_of_tile(int64_t job_id, uint32_t tile, uint32_t next_batch) {
  db_.prepare("DELETE FROM results WHERE job_id = ? AND tile = ? AND batch >= ?")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, next_batch)
      .run();
  return db_.changes();
}

int64_t ResultsTable::drop_waiting_of_job(int64_t job_id) {
  db_.prepare(
         "DELETE FROM results WHERE job_id = ?1 AND batch >= (SELECT t.next_batch FROM tiles t"
         " WHERE t.job_id = ?1 AND t.tile = results.tile)")
      ->bind(1, job_id)
      .run();
  return db_.changes();
}

std::vector<uint32_t> ResultsTable::tiles_with_merged(int64_t job_id) {
  auto q = db_.prepare(
      "SELECT t.tile FROM tiles t WHERE t.job_id = ?1 AND EXISTS (SELECT 1 FROM results r"
      " WHERE r.job_id = ?1 AND r.tile = t.tile AND r.batch < t.next_batch) ORDER BY t.tile");
  return q->bind_all(job_id).rows([](const Statement& r) { return uint32_t(r.int64(0)); });
}

std::vector<uint32_t> ResultsTable::tiles_with_rows(int64_t job_id) {
  auto q = db_.prepare("SELECT DISTINCT tile FROM results WHERE job_id = ? ORDER BY tile");
  return q->bind_all(job_id).rows([](const Statement& r) { return uint32_t(r.int64(0)); });
}

int64_t ResultsTable::count(int64_t job_id) {
  auto q = db_.prepare("SELECT COUNT(*) FROM results WHERE job_id = ?");
  q->bind(1, job_id);
  q->step();
  return q->int64(0);
}

}  // namespace tessera::server
