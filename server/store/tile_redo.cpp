#include "store/tile_redo.h"

namespace tessera::server {

std::vector<std::pair<int64_t, uint32_t>> tiles_delivered_by(Database& db,
                                                             const std::string& worker_name) {
  return db.prepare(
               "SELECT DISTINCT u.job_id, u.tile FROM units u JOIN workers w ON w.id = u.worker_id"
               " JOIN jobs j ON j.id = u.job_id WHERE w.name = ?1 AND u.state = 'done'"
               " AND j.state IN ('queued', 'running') ORDER BY u.job_id, u.tile")
      ->bind_all(worker_name)
      .rows([](const Statement& q) { return std::pair(q.int64(0), uint32_t(q.int64(1))); });
}

int64_t redo_tile(Database& db, int64_t job_id, uint32_t tile) {
  // What the tile counted on its job: merged batches and their samples, accepted units, units
  // the stopping rule skipped (with a row, and unborn ones its close cut off).
  auto q = db.prepare(
      "SELECT t.next_batch, t.spp * (t.x1 - t.x0) * (t.y1 - t.y0),"
      " (SELECT COUNT(*) FROM units u WHERE u.job_id = t.job_id AND u.tile = t.tile"
      "  AND u.state = 'done'),"
      " (SELECT COUNT(*) FROM units u WHERE u.job_id = t.job_id AND u.tile = t.tile"
      "  AND u.state = 'cancelled'),"
      " (SELECT j.batch_count - q.lease_end FROM jobs j, tile_queue q WHERE j.id = t.job_id"
      "  AND q.job_id = t.job_id AND q.tile = t.tile)"
      " FROM tiles t WHERE t.job_id = ?1 AND t.tile = ?2");
  q->bind_all(job_id, tile);
  if (!q->step()) return 0;
  const int64_t merged = q->int64(0), samples = q->int64(1), done = q->int64(2),
                skipped = q->int64(3) + (q->is_null(4) ? 0 : q->int64(4));
  // The redo moves every unit of the tile back to queued, whatever its state (done, leased,
  // or skipped by the rule): the one transition outside the lease state machine
  // (store/job_state.h), made only here.
  db.prepare(
        "UPDATE units SET state = 'queued', lease_id = NULL, worker_id = NULL,"
        " lease_expires_unix_ms = NULL WHERE job_id = ?1 AND tile = ?2 AND state != 'queued'")
      ->bind_all(job_id, tile)
      .run();
  const int64_t requeued = db.changes();
  db.prepare(
        "UPDATE tile_queue SET lease_end = (SELECT batch_count FROM jobs WHERE id = ?1)"
        " WHERE job_id = ?1 AND tile = ?2")
      ->bind_all(job_id, tile)
      .run();
  db.prepare("DELETE FROM results WHERE job_id = ?1 AND tile = ?2")->bind_all(job_id, tile).run();
  db.prepare("DELETE FROM tile_checkpoints WHERE job_id = ?1 AND tile = ?2")
      ->bind_all(job_id, tile)
      .run();
  db.prepare(
        "UPDATE tiles SET next_batch = 0, error = 0, finished = '', spp = 0"
        " WHERE job_id = ?1 AND tile = ?2")
      ->bind_all(job_id, tile)
      .run();
  db.prepare(
        "UPDATE jobs SET units_done = units_done - ?2, results_merged = results_merged - ?3,"
        " samples_merged = samples_merged - ?4, units_skipped = MAX(0, units_skipped - ?5)"
        " WHERE id = ?1")
      ->bind_all(job_id, done, merged, samples, skipped)
      .run();
  return requeued;
}

}  // namespace tessera::server
