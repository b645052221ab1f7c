#include "waiting_results.h"

#include "merge_cache.h"

namespace tessera::server {

void WaitingResults::erase(std::list<Entry>::iterator it) {
  bytes_ -= it->bytes;
  index_.erase(it->key);
  order_.erase(it);
}

void WaitingResults::put(int64_t job_id, uint32_t tile, uint32_t batch, Accumulation result) {
  const Key key{job_id, tile, batch};
  if (const auto found = index_.find(key); found != index_.end()) erase(found->second);
  const size_t bytes = MergeCache::bytes_of(result);
  order_.push_front(Entry{key, std::move(result), bytes});
  index_[key] = order_.begin();
  bytes_ += bytes;
  while (bytes_ > budget_ && !order_.empty()) erase(std::prev(order_.end()));
}

std::optional<Accumulation> WaitingResults::take(int64_t job_id, uint32_t tile, uint32_t batch) {
  const auto found = index_.find({job_id, tile, batch});
  if (found == index_.end()) return std::nullopt;
  std::optional<Accumulation> out = std::move(found->second->result);
  erase(found->second);
  return out;
}

void WaitingResults::forget_job(int64_t job_id) {
  auto it = index_.lower_bound({job_id, 0, 0});
  while (it != index_.end() && std::get<0>(it->first) == job_id) {
    const auto entry = it->second;
    ++it;
    erase(entry);
  }
}

}  // namespace tessera::server
