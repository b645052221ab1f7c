#include "store/tile_queue.h"

namespace tessera::server {

void TileQueue::create(int64_t job_id, uint32_t tiles, uint32_t batch_count) {
  auto insert = db_.prepare(
      "INSERT INTO tile_queue (job_id, tile, next_lease, lease_end) VALUES (?1, ?2, 0, ?3)");
  for (uint32_t t = 0; t < tiles; ++t) {
    insert->reset();
    insert->bind(1, job_id).bind(2, t).bind(3, batch_count);
    insert->run();
  }
}

bool TileQueue::take(int64_t job_id, uint32_t tile, uint32_t batch) {
  db_.prepare(
         "UPDATE tile_queue SET next_lease = next_lease + 1"
         " WHERE job_id = ? AND tile = ? AND next_lease = ? AND next_lease < lease_end")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, batch)
      .run();
  return db_.changes() == 1;
}

int64_t TileQueue::lower_lease_end(int64_t job_id, std::optional<uint32_t> tile,
                                   const std::string& new_end) {
  // `next_lease < lease_end` keeps the statements on the partial index of open rows.
  const std::string where = std::string(" WHERE job_id = ?1") + (tile ? " AND tile = ?2" : "") +
                            " AND next_lease < lease_end AND lease_end > " + new_end;
  int64_t closed = 0;
  {
    auto q = db_.prepare("SELECT COALESCE(SUM(lease_end - " + new_end + "), 0) FROM tile_queue" +
                         where);
    q->bind(1, job_id);
    if (tile) q->bind(2, *tile);
    if (q->step()) closed = q->int64(0);
  }
  auto u = db_.prepare("UPDATE tile_queue SET lease_end = " + new_end + where);
  u->bind(1, job_id);
  if (tile) u->bind(2, *tile);
  u->run();
  return closed;
}

int64_t TileQueue::close_tile(int64_t job_id, uint32_t tile) {
  return lower_lease_end(job_id, tile, "next_lease");
}

int64_t TileQueue::close_job(int64_t job_id) {
  return lower_lease_end(job_id, std::nullopt, "next_lease");
}

int64_t TileQueue::skip_after_first_batch(int64_t job_id) {
  // Past its budget a tile keeps batch 0 if it is still unborn.
  return lower_lease_end(job_id, std::nullopt, "MAX(next_lease, 1)");
}

std::vector<TileQueueRow> TileQueue::rows(int64_t job_id) {
  return db_
      .prepare("SELECT tile, next_lease, lease_end FROM tile_queue WHERE job_id = ? ORDER BY tile")
      ->bind_all(job_id)
      .rows([](const Statement& r) {
        return TileQueueRow{uint32_t(r.int64(0)), uint32_t(r.int64(1)), uint32_t(r.int64(2))};
      });
}

bool TileQueue::any_open(int64_t job_id) {
  auto q = db_.prepare(
      "SELECT 1 FROM tile_queue WHERE job_id = ? AND next_lease < lease_end LIMIT 1");
  q->bind(1, job_id);
  return q->step();
}

}  // namespace tessera::server
