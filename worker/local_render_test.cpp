// The local render's time rule (render_job), on a fake clock: batch 0 of every tile completes,
// and a budget that passes during a later batch cancels that batch's running renders within the
// cancellation's bound, each tile keeping the batches it completed.
#include "local_render.h"

#include <atomic>
#include <chrono>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "render/cancellation.h"
#include "render/renderer.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

using std::chrono::steady_clock;

/// A time job of 2 x 2 tiles of 8 x 8 pixels and fixed batches of `batch` spp, 4 batches.
JobOptions time_job(uint32_t batch) {
  JobOptions o;
  o.width = o.height = 16;
  o.tile_size = 8;
  o.rule = StopRule::time;
  o.time_budget_s = 2;
  o.spp = 4 * batch;
  o.batch_spp = batch;
  o.batch_kind = BatchKind::fixed;
  o.seed = 21;
  o.max_depth = 2;
  return o;
}

/// A clock that stands still until the test moves it; read from rendering threads.
struct RenderClock {
  std::atomic<int64_t> ns{0};
  LocalRenderClock clock() {
    return [this] { return steady_clock::time_point(std::chrono::nanoseconds(ns.load())); };
  }
  void set_seconds(double s) { ns = int64_t(s * 1e9); }
};

bool same_bits(const Accumulation& a, const Accumulation& b) {
  return a.rgb.size() == b.rgb.size() && a.lum2.size() == b.lum2.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(double)) == 0 &&
         std::memcmp(a.lum2.data(), b.lum2.data(), a.lum2.size() * sizeof(double)) == 0 &&
         a.count == b.count;
}

uint64_t samples_in(const LocalRenderResult& r) {
  const std::vector<TileRect> tiles = r.options.plan().tiles();
  uint64_t n = 0;
  for (size_t t = 0; t < tiles.size(); ++t) n += uint64_t(tiles[t].pixel_count()) * r.tile_spp[t];
  return n;
}

// The budget passes as the first unit of batch 1 completes, on two threads: the other thread's
// running render is cancelled at its next poll and no later unit starts, so the renders trace
// at most kMaxSamplesAfterCancel per thread after the budget (the whole rest of batch 1 is
// three units of 64 x 1024 samples, over that bound). Each tile keeps batch 0 and, if it
// completed it, batch 1: the image is bit for bit the merge of exactly those units.
TEST(LocalRender, ABudgetPassingDuringABatchCancelsItsRendersAndKeepsWholeBatches) {
  const Scene scene = test::mixed_room();
  const JobOptions options = time_job(1024);
  const JobPlan plan = options.plan();
  const std::vector<TileRect> tiles = plan.tiles();
  ASSERT_EQ(tiles.size(), 4u);
  const uint64_t batch_samples = uint64_t(options.width) * uint64_t(options.height) * 1024;

  RenderClock clock;
  RenderCancellation user;  // never cancelled: its poll hook counts what the renders trace
  std::atomic<uint64_t> polled{0};
  user.set_poll_hook([&](uint64_t samples) { polled += samples; });
  uint64_t polled_at_budget = 0;
  bool budget_passed = false;
  LocalRenderProgress last;
  constexpr int kThreads = 2;
  LocalRenderResult result;
  tbb::task_arena arena(kThreads);
  arena.execute([&] {
    result = render_job(
        scene, options,
        [&](const LocalRenderProgress& p) {
          last = p;
          if (!budget_passed && p.samples_done > batch_samples) {
            budget_passed = true;
            polled_at_budget = polled.load();
            clock.set_seconds(options.time_budget_s + 0.001);
          }
        },
        IntegratorKind::wavefront, KernelIsa::automatic, &user, clock.clock());
  });

  ASSERT_TRUE(budget_passed);
  EXPECT_EQ(result.reason, StopReason::time_budget);
  // The wavefront renders poll after every pass with its samples: the polls count them all.
  EXPECT_EQ(polled.load(), result.stats.samples);
  EXPECT_LE(result.stats.samples - polled_at_budget,
            uint64_t(kThreads) * RenderCancellation::kMaxSamplesAfterCancel);
  int with_batch_1 = 0;
  for (size_t t = 0; t < tiles.size(); ++t) {
    EXPECT_TRUE(result.tile_spp[t] == 1024 || result.tile_spp[t] == 2048) << "tile " << t;
    with_batch_1 += result.tile_spp[t] == 2048;
  }
  EXPECT_GE(with_batch_1, 1);  // the unit whose completion passed the budget
  EXPECT_LT(with_batch_1, 4);  // two threads' last passes cannot finish three 64k-sample units

  // The image, progress and metadata tell what the image holds; the rate counts all traced,
  // the cancelled render's samples too. (Whether the other thread's render was under way when
  // the budget passed is the scheduler's choice: on a loaded machine it may not have started,
  // and then nothing traced is left out of the image.)
  EXPECT_EQ(last.samples_done, samples_in(result));
  EXPECT_EQ(last.samples_traced, result.stats.samples);
  EXPECT_GE(result.stats.samples, samples_in(result));

  const Renderer renderer(scene, options);
  for (size_t t = 0; t < tiles.size(); ++t) {
    Accumulation expected = renderer.render(tiles[t], 0, 1024);
    if (result.tile_spp[t] == 2048) expected.merge(renderer.render(tiles[t], 1024, 2048));
    EXPECT_TRUE(same_bits(expected, result.tiles[t])) << "tile " << t;
  }
}

// The budget passes during batch 0 (at the renders' first poll): batch 0 of every tile still
// completes, and nothing more starts.
TEST(LocalRender, ABudgetPassingDuringBatch0StillCompletesItInEveryTile) {
  const Scene scene = test::mixed_room();
  const JobOptions options = time_job(16);
  RenderClock clock;
  RenderCancellation user;
  user.set_poll_hook([&](uint64_t) { clock.set_seconds(options.time_budget_s); });
  const LocalRenderResult result = render_job(scene, options, {}, IntegratorKind::wavefront,
                                              KernelIsa::automatic, &user, clock.clock());
  EXPECT_EQ(result.reason, StopReason::time_budget);
  for (size_t t = 0; t < result.tile_spp.size(); ++t) {
    EXPECT_EQ(result.tile_spp[t], 16u) << "tile " << t;
  }
  EXPECT_EQ(result.stats.samples, samples_in(result));
  EXPECT_DOUBLE_EQ(result.seconds, options.time_budget_s);
}

// Ctrl-C during a batch that the budget could cut still ends the render with RenderCancelled,
// never with a part of the job.
TEST(LocalRender, TheUsersCancelDuringALaterBatchOfATimeJobThrows) {
  const Scene scene = test::mixed_room();
  const JobOptions options = time_job(16);
  const uint64_t batch_samples = uint64_t(options.width) * uint64_t(options.height) * 16;
  RenderClock clock;
  RenderCancellation user;
  std::atomic<uint64_t> polled{0};
  user.set_poll_hook([&](uint64_t samples) {
    if ((polled += samples) > batch_samples) user.cancel();
  });
  EXPECT_THROW(render_job(scene, options, {}, IntegratorKind::wavefront, KernelIsa::automatic,
                          &user, clock.clock()),
               RenderCancelled);
  EXPECT_TRUE(user.cancelled());
}

}  // namespace
}  // namespace tessera
