#include "waiting_results.h"

#include "merge_cache.h"

namespace tessera::server {

std::vector<std::pair<int64_t, uint32_t>> WaitingResults::put(int64_t job_id, uint32_t tile,
                                                              uint32_t batch,
                                                              Accumulation result) {
  const size_t bytes = MergeCache::bytes_of(result);
  std::vector<std::pair<int64_t, uint32_t>> evicted;
  lru_.put({job_id, tile, batch}, std::move(result), bytes, [&](const Key& key) {
    evicted.emplace_back(std::get<0>(key), std::get<1>(key));
  });
  return evicted;
}

std::optional<Accumulation> WaitingResults::take(int64_t job_id, uint32_t tile, uint32_t batch) {
  return lru_.take({job_id, tile, batch});
}

void WaitingResults::forget_job(int64_t job_id) {
  lru_.erase_from({job_id, 0, 0},
                  [job_id](const Key& key) { return std::get<0>(key) == job_id; });
}

}  // namespace tessera::server
