// Mitsuba's volume texture lookups (volume_texture.h) against values worked out by hand.
#include "volume_texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/volume_grid_file.h"
#include "scene/volume_grid_test_bytes.h"
#include "texture_set.h"

namespace tessera {
namespace {

/// A grid of resolution `res` and `channels` holding `values` (file order).
std::shared_ptr<const VolumeGridFile> grid_of(glm::ivec3 res, int channels,
                                              std::vector<float> values) {
  auto g = std::make_shared<VolumeGridFile>();
  g->resolution = glm::u32vec3(res);
  g->channels = uint32_t(channels);
  g->values = std::move(values);
  return g;
}

/// 2 x 2 x 2, one channel: v(x, y, z) = x + 2 y + 4 z, a linear function that trilinear
/// interpolation reproduces between the voxel centres (1/4 and 3/4 along each axis).
std::shared_ptr<const VolumeGridFile> ramp() {
  return grid_of({2, 2, 2}, 1, {0, 1, 2, 3, 4, 5, 6, 7});
}

VolumeTexture texture(std::shared_ptr<const VolumeGridFile> g,
                      TextureFilter f = TextureFilter::bilinear, TextureWrap w = TextureWrap::clamp,
                      const glm::dmat4& to_world = glm::dmat4(1.0)) {
  return VolumeTexture(std::move(g), to_world, f, w);
}

TEST(VolumeTexture, TrilinearBetweenVoxelCentres) {
  const VolumeTexture t = texture(ramp());
  EXPECT_NEAR(t.eval_1({0.5f, 0.5f, 0.5f}), 3.5f, 1e-5f);     // the mean of all eight
  EXPECT_NEAR(t.eval_1({0.25f, 0.25f, 0.25f}), 0.0f, 1e-5f);  // voxel (0, 0, 0)'s centre
  EXPECT_NEAR(t.eval_1({0.5f, 0.25f, 0.25f}), 0.5f, 1e-5f);
  EXPECT_NEAR(t.eval_1({0.6f, 0.3f, 0.7f}), 0.7f + 2 * 0.1f + 4 * 0.9f, 1e-5f);
  // Past the last centre the clamped taps repeat the edge: z = 0.9 -> 1.3 - 0.5 past voxel 1.
  EXPECT_NEAR(t.eval_1({0.6f, 0.3f, 0.9f}), 0.7f + 2 * 0.1f + 4 * 1.0f, 1e-5f);
  EXPECT_EQ(t.eval({0.5f, 0.5f, 0.5f}), glm::vec3(3.5f));  // one channel: grey
}

TEST(VolumeTexture, PointsOutsideTheUnitCubeWrapPerAxis) {
  const VolumeTexture clamp = texture(ramp());
  EXPECT_NEAR(clamp.eval_1({-3.0f, 0.25f, 0.25f}), 0.0f, 1e-5f);
  EXPECT_NEAR(clamp.eval_1({5.0f, 0.75f, 0.75f}), 7.0f, 1e-5f);
  EXPECT_NEAR(clamp.eval_1({1.25f, 0.25f, 0.25f}), 1.0f, 1e-5f);
  const VolumeTexture repeat = texture(ramp(), TextureFilter::bilinear, TextureWrap::repeat);
  EXPECT_NEAR(repeat.eval_1({1.25f, 0.25f, 0.25f}), 0.0f, 1e-5f);   // x voxel 2 -> 0
  EXPECT_NEAR(repeat.eval_1({-0.25f, 0.25f, 0.25f}), 1.0f, 1e-5f);  // x voxel -1 -> 1
  EXPECT_NEAR(repeat.eval_1({0.0f, 0.25f, 0.25f}), 0.5f, 1e-5f);    // halfway between 1 and 0
  EXPECT_NEAR(repeat.eval_1({3.25f, 2.25f, -1.75f}), 0.0f, 1e-5f);
  const VolumeTexture mirror = texture(ramp(), TextureFilter::bilinear, TextureWrap::mirror);
  EXPECT_NEAR(mirror.eval_1({1.25f, 0.25f, 0.25f}), 1.0f, 1e-5f);   // x voxel 2 -> 1
  EXPECT_NEAR(mirror.eval_1({-0.25f, 0.25f, 0.25f}), 0.0f, 1e-5f);  // x voxel -1 -> 0
  EXPECT_NEAR(mirror.eval_1({1.75f, 0.25f, 0.25f}), 0.0f, 1e-5f);   // x voxel 3 -> 0
  EXPECT_NEAR(mirror.eval_1({2.25f, 0.25f, 0.25f}), 0.0f, 1e-5f);   // x voxel 4 -> 0
  EXPECT_NEAR(mirror.eval_1({0.25f, 0.25f, -1.25f}), 4.0f, 1e-5f);  // z voxel -3 -> 1
}

TEST(VolumeTexture, MirrorOverThreeVoxels) {
  // Voxel index -> wrapped: ... -2 -> 1, -1 -> 0, 0, 1, 2, 3 -> 2, 4 -> 1, 5 -> 0, 6 -> 0, 7 -> 1.
  const VolumeTexture t = texture(grid_of({3, 1, 1}, 1, {10, 20, 30}), TextureFilter::nearest,
                                  TextureWrap::mirror);
  const float expected[] = {20, 10, 10, 20, 30, 30, 20, 10, 10, 20};
  for (int i = -2; i <= 7; ++i) {
    EXPECT_EQ(t.eval_1({(float(i) + 0.5f) / 3.0f, 0.5f, 0.5f}), expected[i + 2]) << "voxel " << i;
  }
}

TEST(VolumeTexture, NearestTakesTheVoxelHoldingThePoint) {
  const VolumeTexture t = texture(ramp(), TextureFilter::nearest);
  EXPECT_EQ(t.eval_1({0.49f, 0.51f, 0.99f}), 6.0f);
  EXPECT_EQ(t.eval_1({0.5f, 0.0f, 0.0f}), 1.0f);
  EXPECT_EQ(t.eval_1({1.0f, 1.0f, 1.0f}), 7.0f);  // clamped
  EXPECT_EQ(t.eval_1({-0.01f, 0.0f, 0.0f}), 0.0f);
  const VolumeTexture repeat = texture(ramp(), TextureFilter::nearest, TextureWrap::repeat);
  EXPECT_EQ(repeat.eval_1({1.0f, 1.0f, 1.0f}), 0.0f);
  EXPECT_EQ(repeat.eval_1({-0.01f, 0.0f, 0.0f}), 1.0f);
  const VolumeTexture mirror = texture(ramp(), TextureFilter::nearest, TextureWrap::mirror);
  EXPECT_EQ(mirror.eval_1({1.0f, 0.0f, 0.0f}), 1.0f);
  EXPECT_EQ(mirror.eval_1({-0.01f, 0.0f, 0.0f}), 0.0f);
}

TEST(VolumeTexture, ThreeChannels) {
  const VolumeTexture t = texture(grid_of({2, 1, 1}, 3, {1, 0, 0, 0, 1, 0.5f}));
  EXPECT_EQ(t.eval({0.5f, 0.5f, 0.5f}), glm::vec3(0.5f, 0.5f, 0.25f));
  // The scalar lookup is the luminance with Mitsuba's coefficients.
  EXPECT_NEAR(t.eval_1({0.5f, 0.5f, 0.5f}),
              0.5f * 0.212671f + 0.5f * 0.715160f + 0.25f * 0.072169f, 1e-5f);
  EXPECT_EQ(t.eval({0.0f, 0.0f, 0.0f}), glm::vec3(1, 0, 0));
  const glm::vec3 last = t.eval({0.9f, 0.0f, 0.0f});  // past the last centre: voxel 1 alone
  EXPECT_NEAR(last.x, 0.0f, 1e-6f);
  EXPECT_NEAR(last.y, 1.0f, 1e-6f);
  EXPECT_NEAR(last.z, 0.5f, 1e-6f);
}

TEST(VolumeTexture, ToWorldPlacesTheGrid) {
  const glm::dmat4 to_world = glm::scale(glm::translate(glm::dmat4(1.0), {1, 0, 0}), glm::dvec3(2));
  const VolumeTexture t = texture(ramp(), TextureFilter::bilinear, TextureWrap::clamp, to_world);
  // World (2, 0.5, 0.5) is (0.5, 0.25, 0.25) in the grid.
  EXPECT_NEAR(t.eval_1({2.0f, 0.5f, 0.5f}), 0.5f, 1e-5f);
  EXPECT_NEAR(t.eval_1({2.0f, 1.0f, 1.0f}), 3.5f, 1e-5f);
}

TEST(VolumeTexture, Constants) {
  const VolumeTexture grey(glm::vec3(2.5f), true);
  EXPECT_EQ(grey.eval(glm::vec3(7.0f)), glm::vec3(2.5f));
  EXPECT_EQ(grey.eval_1(glm::vec3(7.0f)), 2.5f);
  const VolumeTexture rgb(glm::vec3(0.5f, 2.0f, 1.0f), false);
  EXPECT_EQ(rgb.eval(glm::vec3(-1.0f)), glm::vec3(0.5f, 2.0f, 1.0f));
  EXPECT_NEAR(rgb.eval_1(glm::vec3(0.0f)), 3.5f / 3.0f, 1e-5f);  // Mitsuba's mean(), not luminance
  EXPECT_EQ(rgb.eval(glm::vec2(0.3f, 0.3f)), glm::vec3(0.5f, 2.0f, 1.0f));
}

TEST(VolumeTexture, ExtremesGiveNoNanOrInf) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  const float big = 3e38f, tiny = std::numeric_limits<float>::denorm_min();
  const glm::vec3 points[] = {{0.3f, 0.6f, 0.9f}, {1e30f, -1e30f, 5e37f}, {inf, -inf, nan},
                              {-1e9f, 1e9f, 3.0f}, {2.5e9f, 0.5f, -7e20f}, {0.0f, 1.0f, -0.0f}};
  for (TextureFilter f : {TextureFilter::bilinear, TextureFilter::nearest}) {
    for (TextureWrap w : {TextureWrap::clamp, TextureWrap::repeat, TextureWrap::mirror}) {
      const VolumeTexture one = texture(grid_of({1, 1, 1}, 1, {big}), f, w);
      const VolumeTexture huge = texture(grid_of({2, 1, 2}, 3, {big, tiny, big, big, big, big,
                                                                tiny, big, tiny, big, big, big}),
                                         f, w);
      const VolumeTexture small = texture(grid_of({1, 2, 1}, 1, {tiny, -tiny}), f, w);
      for (const glm::vec3& p : points) {
        // A 1x1x1 grid is its one value everywhere (to the rounding of the weights' sum).
        EXPECT_NEAR(one.eval_1(p), big, 1e-6 * big) << p.x << " " << p.y << " " << p.z;
        const glm::vec3 v = huge.eval(p);
        EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
        EXPECT_TRUE(v.x <= 1.000001f * big && v.y <= 1.000001f * big && v.z <= 1.000001f * big);
        EXPECT_TRUE(std::isfinite(huge.eval_1(p)));
        EXPECT_TRUE(std::isfinite(small.eval_1(p)));
        EXPECT_LE(std::abs(small.eval_1(p)), tiny);
      }
    }
  }
}

TEST(VolumeTexture, TextureSetLooksItUpAtThePointsWorldPosition) {
  Texture grid;
  grid.kind = TextureKind::volume;
  grid.file = "ramp.vol";
  grid.grid = ramp();
  grid.wrap = TextureWrap::clamp;
  Texture constant;
  constant.kind = TextureKind::volume;
  constant.value = glm::dvec3(0.5, 2, 1);
  constant.channels = 3;
  const TextureSet set({grid, constant}, [](const std::string&) -> std::string {
    ADD_FAILURE() << "a volume texture reads no file when the set is made";
    return "";
  });
  TexturePoint at;
  at.uv = {0.25f, 0.25f};  // not what a volume reads
  at.p = {0.5f, 0.25f, 0.25f};
  EXPECT_EQ(set.lookup(0, at), glm::vec3(0.5f));
  EXPECT_EQ(set.lookup_1(0, at), 0.5f);
  EXPECT_EQ(set.lookup(1, at), glm::vec3(0.5f, 2.0f, 1.0f));
  EXPECT_NEAR(set.lookup_1(1, at), 3.5f / 3.0f, 1e-5f);
  // By (u, v) alone (which the loaders never let a volume texture meet) a grid reads 0.
  EXPECT_EQ(set.lookup(0, at.uv), glm::vec3(0.0f));
  EXPECT_EQ(set.lookup_1(0, at.uv), 0.0f);
  EXPECT_EQ(set.eval(TexturedColor{{2, 2, 2}, 0}, at.uv), glm::vec3(0.0f));
}

}  // namespace
}  // namespace tessera
