#include "store/tiles_table.h"

namespace tessera::server {

void TilesTable::insert(int64_t job_id, const std::vector<TileRect>& tiles) {
  for (size_t t = 0; t < tiles.size(); ++t) {
    db_.prepare("INSERT INTO tiles (job_id, tile, x0, y0, x1, y1) VALUES (?, ?, ?, ?, ?, ?)")
        ->bind(1, job_id)
        .bind(2, int64_t(t))
        .bind(3, tiles[t].x0)
        .bind(4, tiles[t].y0)
        .bind(5, tiles[t].x1)
        .bind(6, tiles[t].y1)
        .run();
  }
}

std::vector<TileRecord> TilesTable::of_job(int64_t job_id) {
  std::vector<TileRecord> out;
  auto q = db_.prepare(
      "SELECT t.tile, t.x0, t.y0, t.x1, t.y1, t.next_batch, c.accumulation, t.error, t.finished,"
      " t.spp FROM tiles t LEFT JOIN tile_checkpoints c ON c.job_id = t.job_id AND c.tile = t.tile"
      " WHERE t.job_id = ? ORDER BY t.tile");
  q->bind(1, job_id);
  while (q->step()) {
    TileRecord t;
    t.tile = uint32_t(q->int64(0));
    t.rect = {int(q->int64(1)), int(q->int64(2)), int(q->int64(3)), int(q->int64(4))};
    t.next_batch = uint32_t(q->int64(5));
    if (!q->is_null(6)) t.accumulation = q->blob(6);
    t.error = q->real(7);
    t.finished = stop_reason_from_string(q->text(8)).value_or(StopReason::none);
    t.spp = uint32_t(q->int64(9));
    out.push_back(std::move(t));
  }
  return out;
}

std::optional<TileRect> TilesTable::rect(int64_t job_id, uint32_t tile) {
  return db_.prepare("SELECT x0, y0, x1, y1 FROM tiles WHERE job_id = ? AND tile = ?")
      ->bind_all(job_id, tile)
      .first_row([](const Statement& r) {
        return TileRect{int(r.int64(0)), int(r.int64(1)), int(r.int64(2)), int(r.int64(3))};
      });
}

std::optional<TilePosition> TilesTable::position(int64_t job_id, uint32_t tile) {
  return db_.prepare("SELECT x0, y0, x1, y1, next_batch FROM tiles WHERE job_id = ? AND tile = ?")
      ->bind_all(job_id, tile)
      .first_row([](const Statement& r) {
        return TilePosition{
            {int(r.int64(0)), int(r.int64(1)), int(r.int64(2)), int(r.int64(3))},
            uint32_t(r.int64(4))};
      });
}

std::vector<TilePosition> TilesTable::positions(int64_t job_id) {
  return db_.prepare("SELECT x0, y0, x1, y1, next_batch FROM tiles WHERE job_id = ? ORDER BY tile")
      ->bind_all(job_id)
      .rows([](const Statement& r) {
        return TilePosition{
            {int(r.int64(0)), int(r.int64(1)), int(r.int64(2)), int(r.int64(3))},
            uint32_t(r.int64(4))};
      });
}

std::optional<std::string> TilesTable::checkpoint(int64_t job_id, uint32_t tile) {
  auto q =
      db_.prepare("SELECT accumulation FROM tile_checkpoints WHERE job_id = ? AND tile = ?");
  q->bind(1, job_id).bind(2, tile);
  if (!q->step()) return std::nullopt;
  return q->blob(0);
}

int64_t TilesTable::count_finished_by(int64_t job_id, StopReason reason) {
  auto q = db_.prepare("SELECT COUNT(*) FROM tiles WHERE job_id = ? AND finished = ?");
  q->bind(1, job_id).bind(2, std::string(to_string(reason)));
  q->step();
  return q->int64(0);
}

bool TilesTable::advance(int64_t job_id, uint32_t tile, uint32_t from_next_batch,
                         const TileProgress& p) {
  db_.prepare(
         "UPDATE tiles SET next_batch = ?, error = COALESCE(?, error), finished = ?, spp = ?"
         " WHERE job_id = ? AND tile = ? AND next_batch = ?")
      ->bind(1, p.next_batch)
      .bind(2, p.error)
      .bind(3, std::string(to_string(p.finished)))
      .bind(4, p.spp)
      .bind(5, job_id)
      .bind(6, tile)
      .bind(7, from_next_batch)
      .run();
  return db_.changes() == 1;
}

void TilesTable::write_checkpoint(int64_t job_id, uint32_t tile, const std::string& encoded) {
  db_.prepare(
         "INSERT INTO tile_checkpoints (job_id, tile, accumulation) VALUES (?, ?, ?)"
         " ON CONFLICT (job_id, tile) DO UPDATE SET accumulation = excluded.accumulation")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind_blob_borrowed(3, encoded)  // `encoded` outlives the run
      .run();
}

}  // namespace tessera::server
