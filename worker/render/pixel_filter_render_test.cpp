// The pixel filter through the Renderer: the film positions it draws weigh an image's pixels
// as the filter does.
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "render/camera/pixel_filter_test_support.h"
#include "render/renderer.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

using namespace pixel_filter_test;

/// The renderer draws film positions from Scene::film.filter: an emitter covering exactly the
/// left half of an 8x1 image (its edge between pixels 3 and 4, radiance 1, nothing else in the
/// scene) lights pixel 4 by the filter's weight beyond half a pixel to its left. 256 samples of
/// a (0, 2)-sequence put the sampled fraction within 1/256 of the filter's.
TEST(PixelFilter, TheRendererSamplesTheScenesFilter) {
  Scene s;
  s.camera.position = {0, 0, 1};
  s.camera.look_at = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  s.camera.fov_deg = 90;  // along x: film x in [0, 8) spans X in [-1, 1] on the plane z = 0
  const uint32_t black = test::add_diffuse(s, {0, 0, 0});
  Shape light = test::quad({-10, -10, 0}, {0, -10, 0}, {0, 10, 0}, {-10, 10, 0}, black);
  light.emission = {1, 1, 1};
  s.shapes.push_back(light);
  JobOptions job;
  job.width = 8;
  job.height = 1;
  job.spp = 256;
  job.batch_spp = 256;
  job.seed = 5;
  const auto render = [&](const PixelFilter& f, uint32_t spp = 256,
                          IntegratorKind integrator = IntegratorKind::wavefront) {
    s.film.filter = f;
    job.spp = spp;
    job.batch_spp = spp;
    const Accumulation acc = Renderer(s, job, FileReader(), integrator).render({0, 0, 8, 1}, 0, spp);
    std::vector<double> pixels;
    for (size_t i = 0; i < 8; ++i) pixels.push_back(acc.rgb[i * 3 + 1] / acc.count[i]);
    return pixels;
  };
  const std::vector<double> b = render(box());
  // Which side is lit depends on the camera's handedness; the box tells.
  const bool left_lit = b[0] > 0.5;
  const auto pixel = [&](const std::vector<double>& p, int k) {
    return left_lit ? p[size_t(4 + k)] : p[size_t(3 - k)];
  };
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(pixel(b, k), 0.0) << k;
    EXPECT_EQ(pixel(b, -1 - k), 1.0) << k;
  }
  const std::vector<double> t = render(tent());
  EXPECT_NEAR(pixel(t, 0), 0.125, 1.0 / 256);  // the tent's weight beyond -1/2
  EXPECT_NEAR(pixel(t, -1), 0.875, 1.0 / 256);
  EXPECT_EQ(pixel(t, 1), 0.0);
  const PixelFilter g = gaussian();
  const std::vector<double> gp = render(g);
  const double total = integrate(g, -2, 2, 0);
  EXPECT_NEAR(pixel(gp, 0), integrate(g, -2, -0.5, 0) / total, 1.0 / 256);
  EXPECT_NEAR(pixel(gp, 1), integrate(g, -2, -1.5, 0) / total, 1.0 / 256);
  EXPECT_NEAR(pixel(gp, -1), integrate(g, -2, 0.5, 0) / total, 1.0 / 256);
  // Negative lobes: every pixel within the footprint gets the normalised filter's share,
  // signed, so the one past the edge's neighbour goes negative (Mitsuba's ringing). Samples
  // carry weights of +-(integral |f| / integral f)^2 here (up to 1.8 for lanczos), and the
  // error of 256 samples was up to 0.04 (lanczos; 0.004 with 4096 samples): 4096 samples.
  for (const PixelFilter& f : {mitchell(), lanczos()}) {
    const std::vector<double> p = render(f, 4096);
    const double r = f.radius, all = integrate(f, -r, r, 0);
    for (int k = -3; k <= 3; ++k) {
      const double expected = integrate(f, -r, std::min(r, -0.5 - k), 0) / all;  // light left of pixel 4 + k
      EXPECT_NEAR(pixel(p, k), k >= r + 0.5 ? 0.0 : expected, 2.0 / 256) << int(f.kind) << " pixel " << k;
    }
    // The scalar loop (scenes with media) weighs its samples alike: the same bits.
    EXPECT_EQ(render(f, 4096, IntegratorKind::scalar), p) << int(f.kind);
    const double ringing = integrate(f, -r, -1.5, 0) / all;
    EXPECT_LT(ringing, 0) << int(f.kind);
    EXPECT_LT(pixel(p, 1), ringing / 2) << int(f.kind);
  }
}

}  // namespace
}  // namespace tessera
