// A leased unit's render under its watchdog (unit_render.h): a lease gone or a second stop
// signal stops even one pixel's whole batch, and the partial sums are never returned; an
// unreachable server keeps the render going. Counted in outcomes and samples, never in time.
#include "unit_render.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cstring>

#include "render/testing/test_scenes.h"

namespace tessera::farm {
namespace {

using std::chrono::milliseconds;

JobOptions unit_render_job() {
  JobOptions o;
  o.width = 8;
  o.height = 6;
  o.spp = 1u << 31;
  o.seed = 5;
  o.tile_size = 8;
  o.batch_spp = o.spp;
  return o;
}

// One pixel, 2^31 - 1 samples in one batch: without the sample loop's poll this never ended.
TEST(UnitRender, ALeaseGoneStopsOnePixelsWholeBatchAndDropsItsSums) {
  const Scene scene = test::mixed_room();
  const Renderer renderer(scene, unit_render_job());
  tbb::task_arena arena(2);
  StopSignal stop;
  std::atomic<int> heartbeats{0};
  constexpr uint32_t kSamples = 0x7fffffffu;
  const UnitRenderResult r = render_unit(
      renderer, arena, TileRect{2, 2, 3, 3}, 0, kSamples,
      [&] {
        ++heartbeats;
        return LeaseCheck::gone;
      },
      milliseconds(20), stop);
  EXPECT_EQ(r.outcome, UnitOutcome::lease_lost);
  EXPECT_EQ(heartbeats.load(), 1);
  EXPECT_TRUE(r.result.rgb.empty());
  EXPECT_TRUE(r.result.count.empty());
  EXPECT_LT(r.stats.samples, uint64_t(kSamples));
}

TEST(UnitRender, ASecondStopSignalAbandonsTheUnit) {
  const Scene scene = test::mixed_room();
  const Renderer renderer(scene, unit_render_job());
  tbb::task_arena arena(2);
  StopSignal stop;
  stop.request();
  stop.request();
  const UnitRenderResult r = render_unit(
      renderer, arena, TileRect{0, 0, 8, 6}, 0, 0x7fffffffu, [] { return LeaseCheck::valid; },
      milliseconds(3'600'000), stop);
  EXPECT_EQ(r.outcome, UnitOutcome::abandoned);
  EXPECT_TRUE(r.result.rgb.empty());
}

// The server may be back before the lease ends: the unit is rendered, with the renderer's bits.
TEST(UnitRender, AnUnreachableServerKeepsRenderingTheUnit) {
  const Scene scene = test::mixed_room();
  const Renderer renderer(scene, unit_render_job());
  tbb::task_arena arena(2);
  StopSignal stop;
  const TileRect tile{0, 0, 8, 6};
  const UnitRenderResult r = render_unit(
      renderer, arena, tile, 0, 256, [] { return LeaseCheck::unreachable; }, milliseconds(1), stop);
  ASSERT_EQ(r.outcome, UnitOutcome::rendered);
  EXPECT_EQ(r.stats.samples, uint64_t(tile.pixel_count()) * 256);
  Accumulation direct;
  arena.execute([&] { direct = renderer.render(tile, 0, 256); });
  ASSERT_EQ(r.result.rgb.size(), direct.rgb.size());
  EXPECT_EQ(std::memcmp(r.result.rgb.data(), direct.rgb.data(),
                        direct.rgb.size() * sizeof(double)),
            0);
  EXPECT_EQ(r.result.count, direct.count);
}

}  // namespace
}  // namespace tessera::farm
