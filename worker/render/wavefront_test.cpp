// The wavefront integrator gives the scalar integrator's bits: path by path at every packet
// width, and through the Renderer on every scene of the repository and the Mitsuba test scenes
// (materials, textures, masks, bump maps, instances, environment, spot and projector lights),
// with 1 and 2 threads.
#include <cctype>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "job/job_options.h"
#include "render/integrators/integrator.h"
#include "render/renderer.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"
#include "render/wavefront/kernel_isa.h"
#include "render/wavefront/wavefront_integrator.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

const std::string kSource = TESSERA_SOURCE_DIR;

bool same_bits(const glm::dvec3& a, const glm::dvec3& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

/// Every field of two accumulations, bit for bit; failures name `what` and the first pixel
/// that differs.
void expect_same(const Accumulation& a, const Accumulation& b, const std::string& what) {
  EXPECT_EQ(a.nan_dropped, b.nan_dropped) << what;
  EXPECT_EQ(a.inf_dropped, b.inf_dropped) << what;
  EXPECT_TRUE(a.dropped_examples == b.dropped_examples) << what;
  EXPECT_TRUE(same_bits(a.count, b.count)) << what;
  EXPECT_TRUE(same_bits(a.lum2, b.lum2)) << what;
  ASSERT_EQ(a.rgb.size(), b.rgb.size()) << what;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    if (std::memcmp(&a.rgb[i], &b.rgb[i], sizeof(double)) != 0) {
      const int w = a.rect.width();
      ADD_FAILURE() << what << ": pixel (" << a.rect.x0 + int(i / 3) % w << ", " << a.rect.y0 + int(i / 3) / w
                    << ") channel " << i % 3 << ": " << a.rgb[i] << " against " << b.rgb[i];
      return;
    }
  }
}

TEST(Wavefront, EveryPacketWidthGivesEachPathTheScalarBits) {
  const Scene s = test::mixed_room();
  const TraceableScene scene(s, 24, 18, "");
  constexpr uint64_t kSeed = 3;
  for (const int max_depth : {-1, 3}) {
    std::vector<PathState> start;
    std::vector<PixelSampler> samplers;
    std::vector<glm::dvec3> expected;
    PathCounters scalar_counters;
    for (int y = 0; y < 18; ++y) {
      for (int x = 0; x < 24; ++x) {
        for (uint32_t sample = 0; sample < 4; ++sample) {
          PixelSampler sampler(kSeed, x, y, sample);
          const glm::vec2 u_film = sampler.get2d();
          const glm::vec2 u_lens = sampler.get2d();
          const Ray ray = scene.camera().generate_ray({float(x) + u_film.x, float(y) + u_film.y}, u_lens);
          start.push_back(PathState{ray});
          samplers.push_back(sampler);
          PixelSampler own = sampler;
          expected.push_back(trace_path(scene, ray, max_depth, own, scalar_counters));
        }
      }
    }
    for (const int width : {1, 4, 8, 16}) {
      const WavefrontIntegrator integrator(scene, max_depth, width);
      std::vector<PathState> paths = start;
      std::vector<PixelSampler> own = samplers;
      PathCounters counters;
      WavefrontIntegrator::Workspace workspace;
      integrator.trace(paths, own, counters, workspace);
      EXPECT_EQ(counters.rays, scalar_counters.rays) << "width " << width << ", depth " << max_depth;
      EXPECT_EQ(counters.shadow_rays, scalar_counters.shadow_rays) << "width " << width << ", depth " << max_depth;
      int differences = 0;
      for (size_t i = 0; i < paths.size() && differences < 5; ++i) {
        if (!same_bits(paths[i].radiance, expected[i])) {
          ++differences;
          ADD_FAILURE() << "width " << width << ", depth " << max_depth << ", path " << i << ": "
                        << paths[i].radiance.x << " against " << expected[i].x;
        }
      }
    }
  }
}

TEST(Wavefront, RefusesPathsWithoutSamplers) {
  const Scene s = test::mixed_room();
  const TraceableScene scene(s, 8, 8, "");
  const WavefrontIntegrator integrator(scene, -1, 8);
  std::vector<PathState> paths(3);
  std::vector<PixelSampler> samplers;
  PathCounters counters;
  WavefrontIntegrator::Workspace workspace;
  EXPECT_THROW(integrator.trace(paths, samplers, counters, workspace), std::invalid_argument);
}

// The renderer draws its camera rays' film pairs through draw_pairs: every kernel's, lane-wise
// or one by one, gives get2d's bits, for a count that is no multiple of 16, and leaves the
// samplers where they were.
TEST(Wavefront, DrawPairsGivesEverySamplersOwnPair) {
  const Scene s = test::mixed_room();
  const TraceableScene scene(s, 8, 8, "");
  std::vector<PixelSampler> samplers;
  for (uint32_t i = 0; i < 37; ++i) samplers.emplace_back(uint64_t(11), int(i % 5), int(i / 5), 3 * i + 1);
  for (const KernelIsa isa : {KernelIsa::baseline, KernelIsa::avx2, KernelIsa::avx512}) {
    if (!kernel_isa_supported(isa)) continue;
    const WavefrontIntegrator integrator(scene, -1, 8, isa);
    for (const uint32_t pair : {0u, 5u, PixelSampler::kSobolPairs - 1}) {
      std::vector<glm::vec2> drawn(samplers.size());
      integrator.draw_pairs(samplers.data(), pair, samplers.size(), drawn.data());
      for (size_t i = 0; i < samplers.size(); ++i) {
        PixelSampler own = samplers[i];
        own.set_pair(pair);
        const glm::vec2 expected = own.get2d();
        EXPECT_EQ(drawn[i].x, expected.x) << kernel_isa_name(isa) << ", pair " << pair << ", sampler " << i;
        EXPECT_EQ(drawn[i].y, expected.y) << kernel_isa_name(isa) << ", pair " << pair << ", sampler " << i;
      }
    }
    glm::vec2 out;
    EXPECT_THROW(integrator.draw_pairs(samplers.data(), PixelSampler::kSobolPairs, 1, &out), std::invalid_argument)
        << kernel_isa_name(isa);
  }
}

TEST(Wavefront, IntegratorNames) {
  EXPECT_EQ(integrator_kind_from_name("scalar"), IntegratorKind::scalar);
  EXPECT_EQ(integrator_kind_from_name("wavefront"), IntegratorKind::wavefront);
  EXPECT_STREQ(integrator_kind_name(IntegratorKind::wavefront), "wavefront");
  try {
    integrator_kind_from_name("packets");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("packets"), std::string::npos) << e.what();
  }
}

/// Renders a unit of `scene` with both integrators (the wavefront one with 1 and 2 threads) and
/// expects the same bits: a whole 24x18 image at samples [0, spp), and a tile away from the
/// origin at samples [spp, 2 spp).
void expect_wavefront_equals_scalar(const Scene& scene, const std::string& name, uint32_t spp) {
  JobOverrides overrides;
  overrides.width = 24;
  overrides.height = 18;
  overrides.spp = int64_t(2 * spp);
  overrides.seed = 11;
  const JobOptions options = resolve_job_options(scene, overrides);
  const Renderer scalar(scene, options, {}, IntegratorKind::scalar);
  const Renderer wavefront(scene, options, {}, IntegratorKind::wavefront);
  ASSERT_EQ(wavefront.integrator(), IntegratorKind::wavefront);
  for (const auto& [tile_at, begin_at] : {std::pair{TileRect{0, 0, 24, 18}, 0u}, std::pair{TileRect{5, 3, 21, 17}, spp}}) {
    // Copies: clang 14, the sanitizer build's compiler, cannot capture structured bindings.
    const TileRect tile = tile_at;
    const uint32_t begin = begin_at;
    RenderStats scalar_stats, wavefront_stats;
    const Accumulation expected = scalar.render(tile, begin, begin + spp, &scalar_stats);
    Accumulation one_thread, two_threads;
    tbb::task_arena(1).execute([&] { one_thread = wavefront.render(tile, begin, begin + spp, &wavefront_stats); });
    tbb::task_arena(2).execute([&] { two_threads = wavefront.render(tile, begin, begin + spp); });
    const std::string what = name + ", samples from " + std::to_string(begin);
    expect_same(expected, one_thread, what + ", 1 thread");
    expect_same(expected, two_threads, what + ", 2 threads");
    EXPECT_EQ(scalar_stats.samples, wavefront_stats.samples) << what;
    EXPECT_EQ(scalar_stats.rays, wavefront_stats.rays) << what;
    EXPECT_EQ(scalar_stats.shadow_rays, wavefront_stats.shadow_rays) << what;
  }
}

TEST(Wavefront, MixedSceneGivesTheScalarBits) { expect_wavefront_equals_scalar(test::mixed_room(), "mixed scene", 4); }

class WavefrontScenes : public ::testing::TestWithParam<const char*> {};

TEST_P(WavefrontScenes, GiveTheScalarBits) {
  const Scene scene = load_scene_file(kSource + "/" + GetParam());
  expect_wavefront_equals_scalar(scene, GetParam(), 4);
}

INSTANTIATE_TEST_SUITE_P(
    RepositoryAndMitsubaScenes, WavefrontScenes,
    ::testing::Values("scenes/cornell.json", "scenes/cornell-sphere.json", "scenes/hexroom.json",
                      "scenes/bunny.json", "scenes/cornell-original.xml", "scenes/cornell-sphere.xml",
                      "tests/data/mitsuba/bitmap_texture.xml", "tests/data/mitsuba/envmap.xml",
                      "tests/data/mitsuba/hide_emitters.xml", "tests/data/mitsuba/roughplastic.xml",
                      "tests/data/mitsuba/shapegroup.xml", "tests/data/mitsuba/gaussian_filter.xml",
                      "tests/data/mitsuba/point_spot_constant.xml", "tests/data/mitsuba/projector.xml",
                      "tests/data/mitsuba/spot_texture.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_bumpmap_with.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_conductor_gold.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_dielectric_glass.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_diffuse_textured.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_mask_after.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_plastic_shiny.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_roughconductor_textured_carbon.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_roughdielectric_rough.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_thindielectric_glass.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_twosided_cbox.xml",
                      "tests/data/mitsuba/docs/scenes/shape_bsplinecurve_parameterization.xml",
                      "tests/data/mitsuba/docs/scenes/shape_linearcurve_basic.xml"),
    [](const ::testing::TestParamInfo<const char*>& info) {
      std::string name = info.param;
      name = name.substr(name.rfind('/') + 1);
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

/// Every build of the wavefront loop this machine runs (kernel_isa.h) gives the baseline
/// build's bits, with 1 and 2 threads, Embree pinned to one instruction set for all of them
/// (the widest this CPU has, so packets of 16 on AVX-512 machines). A machine without AVX-512
/// tests baseline and AVX2 only; the test prints which it ran.
class WavefrontKernelScenes : public ::testing::TestWithParam<const char*> {};

TEST_P(WavefrontKernelScenes, EveryKernelGivesTheBaselineBits) {
  const Scene scene = load_scene_file(kSource + "/" + GetParam());
  JobOverrides overrides;
  overrides.width = 24;
  overrides.height = 18;
  overrides.spp = 8;
  overrides.seed = 5;
  overrides.isa = __builtin_cpu_supports("avx512f")  ? "avx512"
                  : __builtin_cpu_supports("avx2") ? "avx2"
                                                   : "sse4.2";
  const JobOptions options = resolve_job_options(scene, overrides);
  const Renderer baseline(scene, options, {}, IntegratorKind::wavefront, KernelIsa::baseline);
  ASSERT_EQ(baseline.kernel_isa(), "baseline");
  const TileRect tile{0, 0, 24, 18};
  Accumulation expected;
  tbb::task_arena(1).execute([&] { expected = baseline.render(tile, 4, 8); });
  std::string tested = "baseline";
  for (const KernelIsa isa : {KernelIsa::baseline, KernelIsa::avx2, KernelIsa::avx512}) {
    if (!kernel_isa_supported(isa)) continue;
    const Renderer renderer(scene, options, {}, IntegratorKind::wavefront, isa);
    ASSERT_EQ(renderer.kernel_isa(), kernel_isa_name(isa));
    Accumulation one_thread, two_threads;
    tbb::task_arena(1).execute([&] { one_thread = renderer.render(tile, 4, 8); });
    tbb::task_arena(2).execute([&] { two_threads = renderer.render(tile, 4, 8); });
    const std::string what = std::string(GetParam()) + ", kernel " + kernel_isa_name(isa) + ", Embree " +
                             renderer.isa();
    expect_same(expected, one_thread, what + ", 1 thread");
    expect_same(expected, two_threads, what + ", 2 threads");
    if (isa != KernelIsa::baseline) tested += std::string(", ") + kernel_isa_name(isa);
  }
  RecordProperty("kernels", tested);
  std::printf("kernels tested: %s (Embree %s)\n", tested.c_str(), baseline.isa().c_str());
}

INSTANTIATE_TEST_SUITE_P(
    RepositoryAndMitsubaScenes, WavefrontKernelScenes,
    ::testing::Values("scenes/cornell.json", "scenes/cornell-sphere.json", "scenes/hexroom.json",
                      "scenes/bunny.json", "tests/data/mitsuba/bitmap_texture.xml", "tests/data/mitsuba/envmap.xml",
                      "tests/data/mitsuba/point_spot_constant.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_dielectric_glass.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_roughconductor_textured_carbon.xml",
                      "tests/data/mitsuba/docs/scenes/bsdf_roughdielectric_rough.xml"),
    [](const ::testing::TestParamInfo<const char*>& info) {
      std::string name = info.param;
      name = name.substr(name.rfind('/') + 1);
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

}  // namespace
}  // namespace tessera
