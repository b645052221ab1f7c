#include "render/guides/guide_tracer.h"

#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "local_render.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

JobOptions guide_job(uint32_t spp, uint32_t batch) {
  JobOptions o = test::test_job(40, 30, spp, -1, 7);
  o.tile_size = 16;
  o.batch_spp = batch;
  return o;
}

bool same_guide_bits(const GuideTile& a, const GuideTile& b) {
  return a.rect == b.rect && a.count == b.count && a.albedo.size() == b.albedo.size() &&
         std::memcmp(a.albedo.data(), b.albedo.data(), a.albedo.size() * sizeof(double)) == 0 &&
         std::memcmp(a.normal.data(), b.normal.data(), a.normal.size() * sizeof(double)) == 0;
}

/// The guide sample of a ray from the camera of test::mixed_room toward `target`.
GuideSample guide_toward(const TraceableScene& scene, glm::vec3 target, uint32_t sample) {
  const glm::vec3 o(0.0f, 0.0f, 0.95f);
  PixelSampler sampler(PixelSampler::pixel_key(7, 3, 4), sample);
  return trace_guide(scene, Ray{o, glm::normalize(target - o)}, sampler);
}

TEST(GuideTracer, AMirrorShowsTheWallItReflects) {
  const TraceableScene scene(test::mixed_room(), 40, 30, "");
  // Straight at the mirror sphere's centre: reflected back to the wall behind the camera
  // (white, 0.7; the inward box's face at z = 1 faces -z).
  const GuideSample g = guide_toward(scene, {0.45f, -0.65f, -0.3f}, 0);
  EXPECT_NEAR(g.albedo.x, 0.7f, 1e-5f);
  EXPECT_NEAR(g.albedo.y, 0.7f, 1e-5f);
  EXPECT_NEAR(g.normal.z, -1.0f, 1e-4f);
}

TEST(GuideTracer, GlassShowsWhatIsBehindIt) {
  const TraceableScene scene(test::mixed_room(), 40, 30, "");
  int through = 0;
  for (uint32_t s = 0; s < 32; ++s) {
    // At the glass sphere's centre, a reflect-or-refract choice by Fresnel (about 4 %
    // reflected) at each face: mostly through to the floor, else back to the wall behind the
    // camera; both white (0.7), and clear glass tints neither.
    const GuideSample g = guide_toward(scene, {-0.4f, -0.6f, 0.0f}, s);
    EXPECT_NEAR(g.albedo.x, 0.7f, 1e-5f) << "sample " << s;
    EXPECT_NEAR(glm::length(g.normal), 1.0f, 1e-4f) << "sample " << s;
    if (g.normal.y > 0.999f) ++through;
  }
  EXPECT_GE(through, 26);
}

TEST(GuideTracer, AnEscapingRayHasNoGuides) {
  Scene s = test::mixed_room();
  s.shapes.erase(s.shapes.begin());  // no box
  const TraceableScene scene(s, 40, 30, "");
  const GuideSample g = guide_toward(scene, {0.0f, 0.5f, -5.0f}, 0);
  EXPECT_EQ(g.albedo, glm::vec3(0.0f));
  EXPECT_EQ(g.normal, glm::vec3(0.0f));
}

TEST(GuideRender, OneThreadAndAllThreadsGiveTheSameBits) {
  const Renderer renderer(test::mixed_room(), guide_job(16, 8));
  const TileRect tile{8, 4, 40, 30};
  GuideTile single, many;
  tbb::task_arena one(1);
  one.execute([&] { single = renderer.render_guides(tile, 4, 12); });
  many = renderer.render_guides(tile, 4, 12);
  EXPECT_TRUE(same_guide_bits(single, many));
  EXPECT_EQ(single.count[0], 8u);
}

TEST(GuideRender, ALocalRenderWithGuidesKeepsItsColourBitsAndItsGuidesAreRepeatable) {
  const Scene scene = test::mixed_room();
  const JobOptions options = guide_job(8, 4);  // two batches, merged in order
  const LocalRenderResult plain = render_job(scene, options);
  LocalRenderResult guided, again;
  guided = render_job(scene, options, {}, IntegratorKind::wavefront, KernelIsa::automatic, nullptr,
                      {}, /*with_guides=*/true);
  tbb::task_arena two(2);
  two.execute([&] {
    again = render_job(scene, options, {}, IntegratorKind::scalar, KernelIsa::automatic, nullptr,
                       {}, /*with_guides=*/true);
  });
  EXPECT_TRUE(plain.guides.empty());
  ASSERT_EQ(plain.tiles.size(), guided.tiles.size());
  ASSERT_EQ(guided.guides.size(), guided.tiles.size());
  for (size_t t = 0; t < plain.tiles.size(); ++t) {
    const std::vector<double>& a = plain.tiles[t].rgb;
    const std::vector<double>& b = guided.tiles[t].rgb;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "tile " << t;
    EXPECT_TRUE(same_guide_bits(guided.guides[t], again.guides[t])) << "tile " << t;
    EXPECT_EQ(guided.guides[t].count[0], 8u);
  }
}

TEST(GuideRender, ALongRenderTakesGuidesFromItsFirstSamplesOnly) {
  JobOptions options = guide_job(100, 24);
  options.width = 8;
  options.height = 6;
  const LocalRenderResult r = render_job(test::mixed_room(), options, {}, IntegratorKind::wavefront,
                                         KernelIsa::automatic, nullptr, {}, /*with_guides=*/true);
  ASSERT_EQ(r.guides.size(), 1u);
  EXPECT_EQ(r.tile_spp[0], 100u);
  for (uint32_t n : r.guides[0].count) EXPECT_EQ(n, kGuideSamples);
  const Renderer renderer(test::mixed_room(), options);
  const GuideTile whole = renderer.render_guides(TileRect{0, 0, 8, 6}, 0, kGuideSamples);
  EXPECT_EQ(whole.count, r.guides[0].count);
}

TEST(GuideTile, ResolvedIntoMeansAndExrChannels) {
  GuideTile tile(TileRect{1, 0, 2, 1});
  tile.albedo = {1.0, 0.5, 0.25};
  tile.normal = {0.0, 0.0, 2.0};
  tile.count = {2};
  GuideTile sum;
  sum.merge(tile);
  sum.merge(tile);
  const GuideImages images = resolve_guides(2, 1, {sum});
  EXPECT_EQ(images.albedo.rgb, (std::vector<float>{0, 0, 0, 0.5f, 0.25f, 0.125f}));
  EXPECT_EQ(images.normal.rgb, (std::vector<float>{0, 0, 0, 0, 0, 1}));
  const std::vector<ExtraChannel> channels = guide_channels(images);
  ASSERT_EQ(channels.size(), 6u);
  EXPECT_EQ(channels[1].name, "albedo.G");
  EXPECT_EQ(channels[1].values, (std::vector<float>{0, 0.25f}));
  EXPECT_EQ(channels[5].name, "N.Z");
  EXPECT_EQ(channels[5].values, (std::vector<float>{0, 1}));
}

}  // namespace
}  // namespace tessera
