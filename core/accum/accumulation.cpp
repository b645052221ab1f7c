#include "accum/accumulation.h"

#include <stdexcept>
#include <string>

namespace tessera {

Accumulation::Accumulation(TileRect r)
    : rect(r),
      rgb(size_t(r.pixel_count()) * 3, 0.0),
      lum2(size_t(r.pixel_count()), 0.0),
      count(size_t(r.pixel_count()), 0) {}

void Accumulation::merge(const Accumulation& next) {
  if (!(next.rect == rect) || next.count.size() != count.size() ||
      next.rgb.size() != rgb.size() || next.lum2.size() != lum2.size()) {
    throw std::invalid_argument("Accumulation::merge: tiles differ");
  }
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] += next.rgb[i];
  for (size_t i = 0; i < lum2.size(); ++i) lum2[i] += next.lum2[i];
  for (size_t i = 0; i < count.size(); ++i) count[i] += next.count[i];
  nan_dropped += next.nan_dropped;
  inf_dropped += next.inf_dropped;
  for (const DroppedSample& d : next.dropped_examples) {
    if (dropped_examples.size() >= kMaxDroppedExamples) break;
    dropped_examples.push_back(d);
  }
}

}  // namespace tessera
