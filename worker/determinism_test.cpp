// The determinism contract at the renderer's level: the same unit gives the same bits whatever
// the threads, and batches rendered in any order merge to the same bits.
#include <algorithm>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "local_render.h"
#include "render/renderer.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

JobOptions job(uint64_t seed, uint32_t spp, uint32_t batch) {
  JobOptions o;
  o.width = 40;
  o.height = 30;
  o.spp = spp;
  o.seed = seed;
  o.tile_size = 16;
  o.batch_spp = batch;
  return o;
}

bool bit_identical(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(Determinism, OneThreadAndAllThreadsGiveTheSameBits) {
  const Scene s = test::mixed_room();
  const Renderer renderer(s, job(5, 64, 16));
  const TileRect tile{8, 4, 40, 30};
  Accumulation single, many;
  tbb::task_arena one(1);
  one.execute([&] { single = renderer.render(tile, 16, 48); });
  many = renderer.render(tile, 16, 48);
  EXPECT_TRUE(bit_identical(single.rgb, many.rgb));
  EXPECT_TRUE(bit_identical(single.lum2, many.lum2));
  EXPECT_EQ(single.count, many.count);
}

// A renderer keeps each thread's path buffers between render() calls (renderer.cpp,
// WavefrontBuffers): whatever an earlier call of another tile, size and sample count left in
// them, a unit's bits are those of a fresh renderer.
TEST(Determinism, EarlierUnitsOfOneRendererDoNotChangeALatersBits) {
  const Scene s = test::mixed_room();
  const TileRect tile{8, 4, 40, 30};
  Accumulation fresh;
  {
    const Renderer renderer(s, job(5, 64, 16));
    fresh = renderer.render(tile, 16, 48);
  }
  const Renderer renderer(s, job(5, 64, 16));
  tbb::task_arena two(2);
  two.execute([&] {
    renderer.render(TileRect{0, 0, 40, 30}, 0, 3);   // 341 pixels a group
    renderer.render(TileRect{0, 0, 7, 5}, 5, 64);    // 17 pixels a group, a short last group
    renderer.render(TileRect{30, 20, 40, 30}, 1, 2); // one sample a pixel
  });
  const Accumulation again = renderer.render(tile, 16, 48);
  EXPECT_TRUE(bit_identical(fresh.rgb, again.rgb));
  EXPECT_TRUE(bit_identical(fresh.lum2, again.lum2));
  EXPECT_EQ(fresh.count, again.count);
}

TEST(Determinism, BatchesRenderedInAnyOrderMergeToTheSameBits) {
  const Scene s = test::mixed_room();
  const JobOptions options = job(9, 64, 8);
  const LocalRenderResult reference = render_job(s, options);

  const Renderer renderer(s, options);
  const JobPlan plan = options.plan();
  const std::vector<TileRect> tiles = plan.tiles();
  std::vector<std::pair<size_t, uint32_t>> units;
  for (size_t t = 0; t < tiles.size(); ++t) {
    for (uint32_t b = 0; b < plan.batch_count(); ++b) units.emplace_back(t, b);
  }
  std::shuffle(units.begin(), units.end(), std::mt19937(77));
  std::vector<std::vector<Accumulation>> results(tiles.size(), std::vector<Accumulation>(plan.batch_count()));
  tbb::task_arena two(2);
  for (const auto& [t, b] : units) {
    two.execute([&, t = t, b = b] {
      results[t][b] = renderer.render(tiles[t], plan.batch_begin(b), plan.batch_end(b));
    });
  }
  for (size_t t = 0; t < tiles.size(); ++t) {
    Accumulation merged(tiles[t]);
    for (uint32_t b = 0; b < plan.batch_count(); ++b) merged.merge(results[t][b]);
    EXPECT_TRUE(bit_identical(merged.rgb, reference.tiles[t].rgb)) << "tile " << t;
    EXPECT_TRUE(bit_identical(merged.lum2, reference.tiles[t].lum2)) << "tile " << t;
    EXPECT_EQ(merged.count, reference.tiles[t].count);
  }
}

TEST(Determinism, ADifferentSeedGivesADifferentImage) {
  const Scene s = test::mixed_room();
  const LocalRenderResult a = render_job(s, job(1, 16, 16));
  const LocalRenderResult b = render_job(s, job(2, 16, 16));
  size_t differing = 0;
  for (size_t t = 0; t < a.tiles.size(); ++t) {
    for (size_t i = 0; i < a.tiles[t].rgb.size(); ++i) differing += a.tiles[t].rgb[i] != b.tiles[t].rgb[i];
  }
  EXPECT_GT(differing, 1000u);
}

TEST(Determinism, MixedSceneStaysFinite) {
  const Scene s = test::mixed_room();
  const LocalRenderResult r = render_job(s, job(3, 32, 32));
  for (const Accumulation& t : r.tiles) {
    EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u);
    for (double v : t.rgb) EXPECT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace tessera
