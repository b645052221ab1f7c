// The camera through the Renderer: what an image shows of a known scene.
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

// An orthographic camera over an emitting rectangle whose edges fall on pixel boundaries:
// every pixel sees all of it or none of it, so each pixel is exactly Le or 0. The view is
// 4 x 2 scene units over 8 x 4 pixels (0.5 per pixel), the rectangle x in [-1, 1.5], y in
// [-0.5, 1]: columns 2..6 and rows 0..2 (image y runs down, against up = +y).
TEST(Camera, OrthographicImageCoversTheViewRectangle) {
  Scene s;
  s.camera.projection = Projection::orthographic;
  s.camera.position = {0.25, 0, 1};
  s.camera.look_at = {0.25, 0, 0};
  s.camera.up = {0, 1, 0};
  s.camera.view_size = {4, 2};
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  Shape light = test::quad({-0.75, -0.5, 0}, {1.75, -0.5, 0}, {1.75, 1, 0}, {-0.75, 1, 0}, m);
  light.emission = {2, 3, 4};
  s.shapes.push_back(light);
  JobOptions job;
  job.width = 8;
  job.height = 4;
  job.spp = 64;
  job.batch_spp = 64;
  job.max_depth = 1;  // the camera ray alone: Le where it hits the rectangle
  const Renderer renderer(s, job);
  const Accumulation acc = renderer.render({0, 0, 8, 4}, 0, 64);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) {
      const size_t i = size_t(y) * 8 + size_t(x);
      const bool lit = x >= 2 && x <= 6 && y <= 2;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(acc.rgb[i * 3 + size_t(c)] / double(acc.count[i]), lit ? 2.0 + c : 0.0,
                    1e-6)
            << "pixel (" << x << ", " << y << ") channel " << c;
      }
    }
  }
}

}  // namespace
}  // namespace tessera
