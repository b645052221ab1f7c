// One Renderer per job (scene bundle + resolved options), kept for the job's next units: building
// the Embree BVH once per job, not once per unit. Holds the few most recent; older ones are
// dropped (a worker moves between jobs rarely).
#pragma once

#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <string>
#include <utility>

#include "render/renderer.h"

namespace tessera::farm {

class RendererCache {
 public:
  explicit RendererCache(size_t capacity = 2) : capacity_(capacity) {}

  /// The renderer cached under `key`, or the one `build()` makes (then cached). Exceptions of
  /// `build` propagate and nothing is cached.
  std::shared_ptr<const Renderer> get(const std::string& key,
                                      const std::function<std::unique_ptr<Renderer>()>& build);

  size_t size() const { return entries_.size(); }

 private:
  size_t capacity_;
  std::list<std::pair<std::string, std::shared_ptr<const Renderer>>> entries_;  ///< most recent first
};

}  // namespace tessera::farm
