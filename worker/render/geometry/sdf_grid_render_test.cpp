// SDF grids through the whole renderer: the torus of Mitsuba's sdfgrid docs scenes in a
// shapegroup placed by an instance (tests/data/mitsuba/sdfgrid/torus_*.xml, smooth and analytic
// normals) read by the importer and rendered as `tessera-worker render` renders it matches
// Mitsuba 3.9.1's image mean (mitsuba_sdfgrid_scene.py -> mitsuba_sdfgrid_scene.txt), and the
// packet (wavefront) integrator gives the same bits as the scalar one.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include <tbb/task_arena.h>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "mitsuba_mean_test_support.h"
#include "render/integrators/integrator.h"
#include "render/renderer.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

TEST(SdfGridRender, TorusScenesMatchMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  const auto means =
      mitsuba_mean::read_mitsuba_means(dir + "/worker/render/geometry/mitsuba_sdfgrid_scene.txt");
  ASSERT_EQ(means.size(), 2u);
  for (const auto& [name, mitsuba] : means) {
    const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/sdfgrid/" + name + ".xml");
    const JobOptions options = resolve_job_options(scene, {});
    ASSERT_EQ(options.width, 64);
    ASSERT_EQ(options.height, 48);
    // A 2-pixel border left out, as mitsuba_sdfgrid_scene.py takes Mitsuba's mean.
    mitsuba_mean::expect_mean_matches_mitsuba(scene, 32, 2, mitsuba, name);
  }
}

/// The wavefront integrator traces packets: its SDF hits (found through Embree's instance
/// transform) must give the scalar integrator's bits, with 1 and 2 threads.
TEST(SdfGridRender, WavefrontGivesTheScalarBits) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  for (const char* name : {"torus_smooth", "torus_analytic"}) {
    const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/sdfgrid/" + name + ".xml");
    JobOverrides overrides;
    overrides.width = 32;
    overrides.height = 24;
    overrides.spp = 4;
    overrides.seed = 11;
    const JobOptions options = resolve_job_options(scene, overrides);
    const Renderer scalar(scene, options, {}, IntegratorKind::scalar);
    const Renderer wavefront(scene, options, {}, IntegratorKind::wavefront);
    ASSERT_EQ(wavefront.integrator(), IntegratorKind::wavefront);
    const TileRect tile{0, 0, 32, 24};
    const Accumulation expected = scalar.render(tile, 0, 4, nullptr);
    for (int threads : {1, 2}) {
      Accumulation got;
      tbb::task_arena(threads).execute([&] { got = wavefront.render(tile, 0, 4, nullptr); });
      EXPECT_EQ(got.nan_dropped + got.inf_dropped, 0u);
      ASSERT_EQ(got.rgb.size(), expected.rgb.size());
      EXPECT_EQ(std::memcmp(got.rgb.data(), expected.rgb.data(), got.rgb.size() * sizeof(got.rgb[0])), 0)
          << name << ", " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace tessera
