#include "merge_cache.h"

namespace tessera::server {

size_t MergeCache::bytes_of(const Accumulation& sum) {
  return sizeof(Entry) + sum.rgb.size() * sizeof(double) + sum.lum2.size() * sizeof(double) +
         sum.count.size() * sizeof(uint32_t) +
         sum.dropped_examples.size() * sizeof(sum.dropped_examples.front());
}

void MergeCache::erase(std::list<Entry>::iterator it) {
  bytes_ -= it->bytes;
  index_.erase(it->key);
  lru_.erase(it);
}

std::optional<MergeCache::Tile> MergeCache::take(int64_t job_id, uint32_t tile,
                                                 uint32_t next_batch) {
  const auto found = index_.find({job_id, tile});
  if (found == index_.end()) return std::nullopt;
  std::optional<Tile> out;
  if (found->second->tile.next_batch == next_batch) out = std::move(found->second->tile);
  erase(found->second);
  return out;
}

void MergeCache::put(int64_t job_id, uint32_t tile, Tile t) {
  const Key key{job_id, tile};
  if (const auto found = index_.find(key); found != index_.end()) erase(found->second);
  const size_t bytes = bytes_of(t.sum);
  lru_.push_front(Entry{key, std::move(t), bytes});
  index_[key] = lru_.begin();
  bytes_ += bytes;
  while (bytes_ > budget_ && !lru_.empty()) erase(std::prev(lru_.end()));
}

void MergeCache::forget_job(int64_t job_id) {
  auto it = index_.lower_bound({job_id, 0});
  while (it != index_.end() && it->first.first == job_id) {
    const auto entry = it->second;
    ++it;
    erase(entry);
  }
}

}  // namespace tessera::server
