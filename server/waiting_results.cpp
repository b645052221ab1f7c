#include "waiting_results.h"

#include "merge_cache.h"

namespace tessera::server {

void WaitingResults::put(int64_t job_id, uint32_t tile, uint32_t batch, Accumulation result) {
  const size_t bytes = MergeCache::bytes_of(result);
  lru_.put({job_id, tile, batch}, std::move(result), bytes);
}

std::optional<Accumulation> WaitingResults::take(int64_t job_id, uint32_t tile, uint32_t batch) {
  return lru_.take({job_id, tile, batch});
}

void WaitingResults::forget_job(int64_t job_id) {
  lru_.erase_from({job_id, 0, 0},
                  [job_id](const Key& key) { return std::get<0>(key) == job_id; });
}

}  // namespace tessera::server
