// Cancelling a render inside a pixel's samples (cancellation.h): counted in samples, never in
// time. A hook trips the cancellation after K samples; the samples traced after the trip stay
// within RenderCancellation::kMaxSamplesAfterCancel per thread, however large the batch, in both
// integrators; nothing of a cancelled render is returned; a render never cancelled keeps its bits.
#include <atomic>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "local_render.h"
#include "render/cancellation.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

JobOptions cancellation_job(uint32_t spp) {
  JobOptions o = test::test_job(24, 18, spp);
  o.tile_size = 16;
  return o;
}

/// Trips `cancel` once the polls have reported at least `trip_after` samples, and records how
/// many they had reported then (at most the samples traced by that moment).
struct CancellationTrip {
  std::atomic<uint64_t> polled{0};
  std::atomic<uint64_t> at_trip{0};
  std::atomic<bool> tripped{false};

  void arm(RenderCancellation& cancel, uint64_t trip_after) {
    cancel.set_poll_hook([this, &cancel, trip_after](uint64_t samples) {
      const uint64_t total = polled.fetch_add(samples) + samples;
      bool expected = false;
      if (total >= trip_after && tripped.compare_exchange_strong(expected, true)) {
        at_trip = total;
        cancel.cancel();
      }
    });
  }
};

struct CancellationCase {
  IntegratorKind integrator;
  const char* name;
};

const CancellationCase kCancellationCases[] = {{IntegratorKind::scalar, "scalar"},
                                               {IntegratorKind::wavefront, "wavefront"}};

bool cancellation_same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The hostile unit: one pixel, 2^24 samples in one batch, so one task on one thread. Before
// the sample loop polled, the render ran to its end and returned.
TEST(RenderCancellation, OnePixelsWholeBatchStopsWithinTheBoundAfterTheTrip) {
  const Scene scene = test::mixed_room();
  constexpr uint32_t kSamples = uint32_t(1) << 24;
  for (const CancellationCase& c : kCancellationCases) {
    const Renderer renderer(scene, cancellation_job(kSamples), {}, c.integrator);
    RenderCancellation cancel;
    CancellationTrip trip;
    trip.arm(cancel, 5000);
    RenderStats stats;
    EXPECT_THROW(renderer.render(TileRect{3, 2, 4, 3}, 0, kSamples, &stats, &cancel),
                 RenderCancelled)
        << c.name;
    ASSERT_TRUE(trip.tripped) << c.name;
    EXPECT_GE(stats.samples, trip.at_trip.load()) << c.name;
    EXPECT_LE(stats.samples - trip.at_trip, RenderCancellation::kMaxSamplesAfterCancel) << c.name;
    EXPECT_LT(stats.samples, uint64_t(kSamples)) << c.name;
  }
}

// A tile of many pixels on every thread of the arena: each thread stops within the bound.
TEST(RenderCancellation, EveryThreadStopsWithinTheBoundAfterTheTrip) {
  const Scene scene = test::mixed_room();
  constexpr uint32_t kSamples = 1u << 14;
  const uint64_t threads = uint64_t(tbb::this_task_arena::max_concurrency());
  for (const CancellationCase& c : kCancellationCases) {
    const Renderer renderer(scene, cancellation_job(kSamples), {}, c.integrator);
    RenderCancellation cancel;
    CancellationTrip trip;
    trip.arm(cancel, 20'000);
    RenderStats stats;
    EXPECT_THROW(renderer.render(TileRect{0, 0, 16, 16}, 0, kSamples, &stats, &cancel),
                 RenderCancelled)
        << c.name;
    ASSERT_TRUE(trip.tripped) << c.name;
    EXPECT_LE(stats.samples - trip.at_trip, threads * RenderCancellation::kMaxSamplesAfterCancel)
        << c.name << ", " << threads << " thread(s)";
  }
}

TEST(RenderCancellation, ACancelBeforeTheRenderTracesNothing) {
  const Scene scene = test::mixed_room();
  for (const CancellationCase& c : kCancellationCases) {
    const Renderer renderer(scene, cancellation_job(64), {}, c.integrator);
    RenderCancellation cancel;
    cancel.cancel();
    RenderStats stats;
    EXPECT_THROW(renderer.render(TileRect{0, 0, 16, 16}, 0, 64, &stats, &cancel), RenderCancelled)
        << c.name;
    EXPECT_EQ(stats.samples, 0u) << c.name;
  }
}

// Polled (hook set, never tripped) or not given at all: the same bits, the same samples.
TEST(RenderCancellation, AnUncancelledRenderKeepsItsBits) {
  const Scene scene = test::mixed_room();
  for (const CancellationCase& c : kCancellationCases) {
    // More samples per pixel than one wavefront pass holds, so pixels span passes and polls.
    constexpr uint32_t kSpp = 1100;
    const Renderer renderer(scene, cancellation_job(kSpp), {}, c.integrator);
    const TileRect tile{4, 2, 12, 10};
    RenderStats plain_stats, polled_stats;
    const Accumulation plain = renderer.render(tile, 0, kSpp, &plain_stats);
    RenderCancellation cancel;
    std::atomic<uint64_t> polls{0};
    cancel.set_poll_hook([&](uint64_t) { ++polls; });
    const Accumulation polled = renderer.render(tile, 0, kSpp, &polled_stats, &cancel);
    EXPECT_GT(polls.load(), 0u) << c.name;
    EXPECT_TRUE(cancellation_same_bits(plain.rgb, polled.rgb)) << c.name;
    EXPECT_TRUE(cancellation_same_bits(plain.lum2, polled.lum2)) << c.name;
    EXPECT_EQ(plain.count, polled.count) << c.name;
    EXPECT_EQ(plain_stats.samples, polled_stats.samples) << c.name;
  }
}

// `tessera-worker render` (SignalCancellation trips the same token): the local render throws
// rather than return a part of the job.
TEST(RenderCancellation, ALocalRenderStopsAndReturnsNothing) {
  const Scene scene = test::mixed_room();
  JobOptions options = cancellation_job(uint32_t(1) << 22);
  options.width = options.height = 2;
  RenderCancellation cancel;
  CancellationTrip trip;
  trip.arm(cancel, 3000);
  EXPECT_THROW(
      render_job(scene, options, {}, IntegratorKind::wavefront, KernelIsa::automatic, &cancel),
      RenderCancelled);
  EXPECT_TRUE(trip.tripped);
}

}  // namespace
}  // namespace tessera
