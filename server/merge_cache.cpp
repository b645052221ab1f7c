#include "merge_cache.h"

namespace tessera::server {

size_t MergeCache::bytes_of(const Accumulation& sum) {
  return ByteBoundedLru<Key, Tile>::kEntryBytes + sum.rgb.size() * sizeof(double) +
         sum.lum2.size() * sizeof(double) + sum.count.size() * sizeof(uint32_t) +
         sum.dropped_examples.size() * sizeof(sum.dropped_examples.front());
}

std::optional<MergeCache::Tile> MergeCache::take(int64_t job_id, uint32_t tile,
                                                 uint32_t next_batch) {
  std::optional<Tile> out = lru_.take({job_id, tile});
  if (out && out->next_batch != next_batch) out.reset();  // stale: dropped
  return out;
}

void MergeCache::put(int64_t job_id, uint32_t tile, Tile t) {
  const size_t bytes = bytes_of(t.sum);
  lru_.put({job_id, tile}, std::move(t), bytes);
}

void MergeCache::forget_job(int64_t job_id) {
  lru_.erase_from({job_id, 0}, [job_id](const Key& key) { return key.first == job_id; });
}

}  // namespace tessera::server
