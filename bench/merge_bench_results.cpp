#include "merge_bench_results.h"

#include <cmath>
#include <random>

namespace tessera::bench_merge {

Accumulation noisy_accumulation(const TileRect& rect, uint32_t samples, uint64_t seed) {
  Accumulation acc(rect);
  std::mt19937_64 rng(seed);
  std::exponential_distribution<float> noise(1.0f);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  size_t i = 0;
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x, ++i) {
      const float base[3] = {0.5f + 0.3f * std::sin(float(x) * 0.05f),
                             0.4f + 0.2f * std::cos(float(y) * 0.07f), 0.3f};
      for (uint32_t s = 0; s < samples; ++s) {
        const float scale = noise(rng) * (u01(rng) < 0.01f ? 40.0f : 1.0f);
        float rgb[3];
        for (int c = 0; c < 3; ++c) rgb[c] = base[c] * scale;
        for (int c = 0; c < 3; ++c) acc.rgb[3 * i + size_t(c)] += double(rgb[c]);
        const double y_lum = luminance(rgb[0], rgb[1], rgb[2]);
        acc.lum2[i] += y_lum * y_lum;
      }
      acc.count[i] = samples;
    }
  }
  return acc;
}

}  // namespace tessera::bench_merge
