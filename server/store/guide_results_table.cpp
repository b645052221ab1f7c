#include "store/guide_results_table.h"

namespace tessera::server {

bool GuideResultsTable::put(int64_t job_id, uint32_t tile, uint32_t batch,
                            const std::string& encoded) {
  db_.prepare(
         "INSERT OR REPLACE INTO guide_results (job_id, tile, batch, guides)"
         " SELECT ?1, ?2, ?3, ?4 FROM jobs WHERE id = ?1 AND denoise = 1")
      ->bind(1, job_id)
      .bind(2, tile)
      .bind(3, batch)
      .bind_blob_borrowed(4, encoded)  // `encoded` outlives the run
      .run();
  return db_.changes() == 1;
}

void GuideResultsTable::for_each_below(
    int64_t job_id, uint32_t tile, uint32_t next_batch,
    const std::function<void(uint32_t, const std::string&)>& each) {
  auto q = db_.prepare(
      "SELECT batch, guides FROM guide_results WHERE job_id = ? AND tile = ? AND batch < ?"
      " ORDER BY batch");
  q->bind(1, job_id).bind(2, tile).bind(3, next_batch);
  while (q->step()) each(uint32_t(q->int64(0)), q->blob(1));
}

}  // namespace tessera::server
