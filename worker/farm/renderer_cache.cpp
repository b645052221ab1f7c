#include "renderer_cache.h"

namespace tessera::farm {

std::shared_ptr<const Renderer> RendererCache::get(
    const std::string& key, const std::function<std::unique_ptr<Renderer>()>& build) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if (it->first == key) {
      entries_.splice(entries_.begin(), entries_, it);
      return entries_.front().second;
    }
  }
  std::shared_ptr<const Renderer> renderer = build();
  entries_.emplace_front(key, renderer);
  while (entries_.size() > capacity_) entries_.pop_back();
  return renderer;
}

}  // namespace tessera::farm
