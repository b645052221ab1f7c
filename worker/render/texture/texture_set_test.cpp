#include "texture_set.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Imath/half.h>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "scene/scene_error.h"
#include "srgb.h"
#include "texture_test_images.h"

namespace tessera {
namespace {

using test::encode_image;
using test::memory_reader;

/// What Mitsuba fetches for an 8-bit sRGB code: the decoded value in float.
float srgb8(int code) { return float(srgb_to_linear(code / 255.0)); }
float half_of(double v) { return float(Imath::half(float(v))); }

Texture bitmap(const std::string& file, TextureWrap wrap = TextureWrap::repeat,
               TextureFilter filter = TextureFilter::bilinear,
               TextureColorSpace cs = TextureColorSpace::srgb) {
  Texture t;
  t.kind = TextureKind::bitmap;
  t.name = file;
  t.origin = "textures[0]";
  t.file = file;
  t.wrap = wrap;
  t.filter = filter;
  t.color_space = cs;
  return t;
}

/// 3x2 RGB, 8 bits: row 0 is the top row of the file.
const std::vector<uint8_t> kRgb8 = {0,  0,  0,  128, 64,  255, 255, 255, 255,  // row 0
                                    10, 20, 30, 200, 100, 50,  1,   2,   3};   // row 1

/// 3x2 one channel, float: linear values kept exactly (0.1 is not a half).
const std::vector<float> kWrap = {0.1f, 2, 3,   // row 0
                                  4,    5, 6};  // row 1

std::map<std::string, std::string> test_files() {
  return {
      {"rgb8.png", encode_image("rgb8.png", 3, 2, 3, kRgb8, OIIO::TypeDesc::UINT8)},
      {"wrap.exr", encode_image("wrap.exr", 3, 2, 1, kWrap, OIIO::TypeDesc::FLOAT)},
  };
}

glm::vec2 centre(int x, int y, int w, int h) {
  return {(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)};
}

TEST(TextureSet, EightBitSrgbTexelsAreDecoded) {
  const TextureSet set({bitmap("rgb8.png")}, memory_reader(test_files()));
  ASSERT_FALSE(set.empty());
  // By hand: ((128 / 255 + 0.055) / 1.055)^2.4 = 0.21586050...; Mitsuba 3.9.1 fetches
  // 0.21586041 (Dr.Jit approximates the transfer function to 4e-7).
  EXPECT_EQ(srgb8(128), 0.2158605f);
  EXPECT_EQ(set.lookup(0, centre(1, 0, 3, 2)), glm::vec3(0.2158605f, srgb8(64), 1.0f));
  EXPECT_EQ(set.lookup(0, centre(0, 0, 3, 2)), glm::vec3(0.0f));
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) {
      const uint8_t* c = &kRgb8[size_t(y * 3 + x) * 3];
      EXPECT_EQ(set.lookup(0, centre(x, y, 3, 2)), glm::vec3(srgb8(c[0]), srgb8(c[1]), srgb8(c[2])))
          << x << "," << y;
    }
  }
}

TEST(TextureSet, RawEightBitTexelsAreCodesOver255) {
  const TextureSet set(
      {bitmap("rgb8.png", TextureWrap::repeat, TextureFilter::bilinear, TextureColorSpace::linear)},
      memory_reader(test_files()));
  EXPECT_EQ(set.lookup(0, centre(1, 1, 3, 2)),
            glm::vec3(float(200 / 255.0), float(100 / 255.0), float(50 / 255.0)));
}

TEST(TextureSet, BilinearInterpolatesBetweenTexelCentres) {
  const TextureSet set({bitmap("rgb8.png")}, memory_reader(test_files()));
  // u = 0.25: image x = 0.25 * 3 - 0.5 = 0.25, a quarter of the way from texel 0 to texel 1;
  // v = 0.5: halfway between rows 0 and 1.
  const glm::vec3 t00(srgb8(0), srgb8(0), srgb8(0)), t10(srgb8(128), srgb8(64), srgb8(255));
  const glm::vec3 t01(srgb8(10), srgb8(20), srgb8(30)), t11(srgb8(200), srgb8(100), srgb8(50));
  const glm::vec3 expected = 0.375f * t00 + 0.125f * t10 + 0.375f * t01 + 0.125f * t11;
  const glm::vec3 got = set.lookup(0, {0.25f, 0.5f});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-6f) << c;
}

TEST(TextureSet, SixteenBitAndAlphaImages) {
  const std::vector<uint16_t> y16 = {0, 32768, 65535, 1000};
  const std::vector<uint8_t> rgba = {200, 100, 50, 0, 10, 20, 30, 255, 1, 2, 3, 128, 4, 5, 6, 7};
  const std::vector<uint8_t> ya = {128, 0, 255, 255, 0, 10, 64, 200};
  const TextureSet set(
      {bitmap("y16.png"), bitmap("rgba.png"), bitmap("ya.png")},
      memory_reader({{"y16.png", encode_image("y16.png", 2, 2, 1, y16, OIIO::TypeDesc::UINT16)},
                     {"rgba.png", encode_image("rgba.png", 2, 2, 4, rgba, OIIO::TypeDesc::UINT8)},
                     {"ya.png", encode_image("ya.png", 2, 2, 2, ya, OIIO::TypeDesc::UINT8)}}));
  const float y = half_of(srgb_to_linear(32768 / 65535.0));
  EXPECT_EQ(set.lookup(0, centre(1, 0, 2, 2)), glm::vec3(y));
  EXPECT_EQ(set.lookup_1(0, centre(1, 1, 2, 2)), half_of(srgb_to_linear(1000 / 65535.0)));
  // Alpha 0 does not darken the colour: it is dropped, never multiplied in.
  EXPECT_EQ(set.lookup(1, centre(0, 0, 2, 2)), glm::vec3(srgb8(200), srgb8(100), srgb8(50)));
  EXPECT_EQ(set.lookup(2, centre(0, 0, 2, 2)), glm::vec3(srgb8(128)));
  EXPECT_EQ(set.lookup(2, centre(1, 1, 2, 2)), glm::vec3(srgb8(64)));
}

TEST(TextureSet, FloatImagesAreUsedAsStoredEvenWhenMarkedSrgb) {
  const TextureSet set(
      {bitmap("wrap.exr", TextureWrap::repeat, TextureFilter::nearest, TextureColorSpace::srgb)},
      memory_reader(test_files()));
  EXPECT_EQ(set.lookup(0, centre(0, 0, 3, 2)), glm::vec3(0.1f));
  EXPECT_EQ(set.lookup(0, centre(2, 1, 3, 2)), glm::vec3(6.0f));
}

TEST(TextureSet, NearestLookupsWrapLikeMitsuba) {
  const TextureSet set({bitmap("wrap.exr", TextureWrap::repeat, TextureFilter::nearest),
                        bitmap("wrap.exr", TextureWrap::mirror, TextureFilter::nearest),
                        bitmap("wrap.exr", TextureWrap::clamp, TextureFilter::nearest)},
                       memory_reader(test_files()));
  const float sixth = 1.0f / 6.0f;
  struct Case {
    glm::vec2 uv;
    float repeat, mirror, clamp;
  };
  // Row 0 is 0.1 2 3, row 1 is 4 5 6. u * 3 and v * 2 select the texel.
  const Case cases[] = {
      {{sixth, 0.25f}, 0.1f, 0.1f, 0.1f},   // texel (0, 0)
      {{-sixth, 0.25f}, 3, 0.1f, 0.1f},     // x = -1: wraps to 2, mirrors to 0
      {{1 + sixth, 0.25f}, 0.1f, 3, 3},     // x = 3: period 1
      {{2 + sixth, 0.25f}, 0.1f, 0.1f, 3},  // x = 6: period 2 (mirror back to normal)
      {{-1 - sixth, 0.25f}, 3, 3, 0.1f},    // x = -4: period -2
      {{0.5f, 0.75f}, 5, 5, 5},             // texel (1, 1)
      {{0.5f, -0.25f}, 5, 2, 2},            // y = -1
      {{0.5f, 1.25f}, 2, 5, 5},             // y = 2
  };
  for (const Case& c : cases) {
    EXPECT_EQ(set.lookup_1(0, c.uv), c.repeat) << c.uv.x << "," << c.uv.y;
    EXPECT_EQ(set.lookup_1(1, c.uv), c.mirror) << c.uv.x << "," << c.uv.y;
    EXPECT_EQ(set.lookup_1(2, c.uv), c.clamp) << c.uv.x << "," << c.uv.y;
  }
}

TEST(TextureSet, BilinearLookupsWrapAtTheBorder) {
  const TextureSet set(
      {bitmap("wrap.exr", TextureWrap::repeat), bitmap("wrap.exr", TextureWrap::mirror),
       bitmap("wrap.exr", TextureWrap::clamp)},
      memory_reader(test_files()));
  // u = 0, v = 0.25: image x = -0.5 (halfway between texels -1 and 0), row 0 exactly.
  EXPECT_FLOAT_EQ(set.lookup_1(0, {0.0f, 0.25f}), 0.5f * 3 + 0.5f * 0.1f);
  EXPECT_FLOAT_EQ(set.lookup_1(1, {0.0f, 0.25f}), 0.1f);
  EXPECT_FLOAT_EQ(set.lookup_1(2, {0.0f, 0.25f}), 0.1f);
  // v = 0: image y = -0.5, between rows -1 (repeat: row 1) and 0.
  EXPECT_FLOAT_EQ(set.lookup_1(0, {0.5f, 0.0f}), 0.5f * 5 + 0.5f * 2);
  EXPECT_FLOAT_EQ(set.lookup_1(2, {0.5f, 0.0f}), 2.0f);
}

TEST(TextureSet, ToUvMapsCoordinatesBeforeTheLookup) {
  Texture shifted = bitmap("wrap.exr", TextureWrap::repeat, TextureFilter::nearest);
  shifted.to_uv = glm::dmat3(2, 0, 0,  // column 0: u' = 2 u + 1/3
                             0, 1, 0,  // column 1: v' = v + 1/2
                             1.0 / 3, 0.5, 1);
  const TextureSet set({shifted}, memory_reader(test_files()));
  // u = 0.1 -> u' = 0.5333 (texel 1); v = 0.1 -> v' = 0.6 (row 1).
  EXPECT_EQ(set.lookup_1(0, {0.1f, 0.1f}), 5.0f);
  // u = 0.4 -> u' = 1.1333 (texel 0 of the next period); v = 0.6 -> 1.1 (row 0).
  EXPECT_EQ(set.lookup_1(0, {0.4f, 0.6f}), 0.1f);
}

TEST(TextureSet, CheckerboardFollowsMitsubasPattern) {
  Texture c;
  c.kind = TextureKind::checkerboard;
  c.color0 = {1, 0, 0};
  c.color1 = {0, 0, 1};
  Texture scaled = c;
  scaled.to_uv = glm::dmat3(2.0);
  scaled.to_uv[2][2] = 1;
  const TextureSet set({c, scaled}, memory_reader({}));
  const glm::vec3 c0(1, 0, 0), c1(0, 0, 1);
  EXPECT_EQ(set.lookup(0, {0.1f, 0.1f}), c0);
  EXPECT_EQ(set.lookup(0, {0.6f, 0.1f}), c1);
  EXPECT_EQ(set.lookup(0, {0.1f, 0.6f}), c1);
  EXPECT_EQ(set.lookup(0, {0.6f, 0.6f}), c0);
  EXPECT_EQ(set.lookup(0, {-0.1f, 0.1f}), c1);  // fraction 0.9
  EXPECT_EQ(set.lookup(0, {1.1f, 0.1f}), c0);
  EXPECT_EQ(set.lookup(0, {0.5f, 0.1f}), c0);  // a fraction of exactly 1/2 is the low half
  EXPECT_EQ(set.lookup(1, {0.3f, 0.1f}), c1);  // (0.6, 0.2) after to_uv
  EXPECT_EQ(set.gradient(0, {0.3f, 0.3f}), glm::vec2(0.0f));
  // The scalar lookup takes the colours the other way round, as Mitsuba 3.9.1's eval_1 does.
  EXPECT_FLOAT_EQ(set.lookup_1(0, {0.1f, 0.1f}), 0.072169f);
  EXPECT_FLOAT_EQ(set.lookup_1(0, {0.6f, 0.1f}), 0.212671f);
}

TEST(TextureSet, RawConstantsAreTheSameEverywhereAndUnconverted) {
  Texture one;
  one.kind = TextureKind::rawconstant;
  one.value = glm::dvec3(1.5);
  one.channels = 1;
  Texture three = one;
  three.value = {0.5, -0.25, 1};
  three.channels = 3;
  const TextureSet set({one, three}, memory_reader({}));
  for (glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(0.3f, 7.5f), glm::vec2(-2, 0.5f)}) {
    EXPECT_EQ(set.lookup(0, uv), glm::vec3(1.5f));
    EXPECT_EQ(set.lookup_1(0, uv), 1.5f);
    EXPECT_EQ(set.lookup(1, uv), glm::vec3(0.5f, -0.25f, 1));
    EXPECT_FLOAT_EQ(set.lookup_1(1, uv), 0.212671f * 0.5f - 0.715160f * 0.25f + 0.072169f);
    EXPECT_EQ(set.gradient(0, uv), glm::vec2(0.0f));
  }
}

TEST(TextureSet, TexturedParametersScaleTheLookup) {
  const TextureSet set({bitmap("rgb8.png")}, memory_reader(test_files()));
  const TexturedColor constant{{0.25, 0.5, 0.75}, -1};
  EXPECT_EQ(set.eval(constant, {0.3f, 0.3f}), glm::vec3(0.25f, 0.5f, 0.75f));
  const TexturedColor textured{{2, 1, 0.5}, 0};
  const glm::vec3 t = set.lookup(0, centre(1, 1, 3, 2));
  EXPECT_EQ(set.eval(textured, centre(1, 1, 3, 2)), glm::vec3(2 * t.x, t.y, 0.5f * t.z));
  const TexturedFloat scalar{0.5, 0};
  const float lum = 0.212671f * t.x + 0.715160f * t.y + 0.072169f * t.z;
  EXPECT_FLOAT_EQ(set.eval(scalar, centre(1, 1, 3, 2)), 0.5f * lum);
  EXPECT_EQ(set.eval(TexturedFloat{0.3, -1}, {0.0f, 0.0f}), 0.3f);
  EXPECT_THROW(set.lookup(1, {0, 0}), std::out_of_range);
}

TEST(TextureSet, AOneTexelImageIsConstant) {
  const std::vector<uint8_t> red = {255, 0, 0};
  const TextureSet set(
      {bitmap("one.png")},
      memory_reader({{"one.png", encode_image("one.png", 1, 1, 3, red, OIIO::TypeDesc::UINT8)}}));
  for (const glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(0.3f, 0.9f), glm::vec2(-2.5f, 7.25f)}) {
    EXPECT_EQ(set.lookup(0, uv), glm::vec3(1, 0, 0));
  }
  EXPECT_EQ(set.gradient(0, {0.3f, 0.6f}), glm::vec2(0.0f));
}

/// Central differences of the scalar lookup, away from the lines through texel centres where
/// the bilinear interpolant has kinks.
void expect_gradient_matches_differences(const TextureSet& set, int texture,
                                         const glm::dmat3& to_uv, int w, int h) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(-1.5f, 2.5f);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::vec2 uv(uniform(rng), uniform(rng));
    const glm::dvec3 p = to_uv * glm::dvec3(uv.x, uv.y, 1);
    const double px = p.x * w - 0.5, py = p.y * h - 0.5;
    if (std::abs(px - std::round(px)) < 0.02 || std::abs(py - std::round(py)) < 0.02) continue;
    const float eps = 1e-3f;
    const glm::vec2 g = set.gradient(texture, uv);
    const float du =
        (set.lookup_1(texture, {uv.x + eps, uv.y}) - set.lookup_1(texture, {uv.x - eps, uv.y})) /
        (2 * eps);
    const float dv =
        (set.lookup_1(texture, {uv.x, uv.y + eps}) - set.lookup_1(texture, {uv.x, uv.y - eps})) /
        (2 * eps);
    EXPECT_NEAR(g.x, du, 2e-3f * (1 + std::abs(du))) << uv.x << "," << uv.y;
    EXPECT_NEAR(g.y, dv, 2e-3f * (1 + std::abs(dv))) << uv.x << "," << uv.y;
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

TEST(TextureSet, GradientEqualsFiniteDifferences) {
  // A rotated, scaled to_uv on a non-square image: the chain rule through both axes matters.
  const double c = std::cos(0.5), s = std::sin(0.5);
  const glm::dmat3 rotated(1.3 * c, 0.7 * s, 0, -1.3 * s, 0.7 * c, 0, 0.2, -0.1, 1);
  Texture a = bitmap("wrap.exr", TextureWrap::repeat);
  a.to_uv = rotated;
  Texture b = bitmap("rgb8.png", TextureWrap::mirror);
  b.to_uv = rotated;
  const TextureSet set({a, b, bitmap("wrap.exr", TextureWrap::clamp)}, memory_reader(test_files()));
  expect_gradient_matches_differences(set, 0, rotated, 3, 2);
  expect_gradient_matches_differences(set, 1, rotated, 3, 2);
  expect_gradient_matches_differences(set, 2, glm::dmat3(1.0), 3, 2);
  // Nearest filtering is piecewise constant.
  const TextureSet nearest({bitmap("wrap.exr", TextureWrap::repeat, TextureFilter::nearest)},
                           memory_reader(test_files()));
  EXPECT_EQ(nearest.gradient(0, {0.3f, 0.3f}), glm::vec2(0.0f));
}

TEST(TextureSet, ParallelLookupsEqualSerialOnes) {
  const TextureSet set({bitmap("rgb8.png"), bitmap("wrap.exr", TextureWrap::mirror)},
                       memory_reader(test_files()));
  const int n = 200000;
  std::vector<glm::vec2> uvs(n);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(-3.0f, 3.0f);
  for (glm::vec2& uv : uvs) uv = {uniform(rng), uniform(rng)};
  std::vector<glm::vec3> serial(n), parallel(n);
  std::vector<glm::vec2> serial_g(n), parallel_g(n);
  for (int i = 0; i < n; ++i) {
    serial[size_t(i)] = set.lookup(i % 2, uvs[size_t(i)]);
    serial_g[size_t(i)] = set.gradient(i % 2, uvs[size_t(i)]);
  }
  tbb::parallel_for(0, n, [&](int i) {
    parallel[size_t(i)] = set.lookup(i % 2, uvs[size_t(i)]);
    parallel_g[size_t(i)] = set.gradient(i % 2, uvs[size_t(i)]);
  });
  EXPECT_EQ(std::memcmp(serial.data(), parallel.data(), serial.size() * sizeof(glm::vec3)), 0);
  EXPECT_EQ(std::memcmp(serial_g.data(), parallel_g.data(), serial_g.size() * sizeof(glm::vec2)),
            0);
}

void expect_refused(const std::string& file, const std::string& bytes,
                    const std::vector<std::string>& parts) {
  try {
    TextureSet set({bitmap(file)}, memory_reader({{file, bytes}}));
    FAIL() << "accepted " << file;
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("textures[0]: " + file + ": ", 0), 0u) << what;
    for (const std::string& p : parts) EXPECT_NE(what.find(p), std::string::npos) << what;
  }
}

TEST(TextureSet, RefusesBadTexelsAndUndecodableBytesNamingTheFile) {
  const float nan = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  expect_refused(
      "nan.exr",
      encode_image("nan.exr", 2, 2, 3, std::vector<float>{0, 0, 0, 1, nan, 1, 0, 0, 0, 0, 0, 0},
                   OIIO::TypeDesc::FLOAT),
      {"texel (1, 0) channel 1 is NaN"});
  expect_refused(
      "inf.exr",
      encode_image("inf.exr", 2, 2, 1, std::vector<float>{0, 0, 0, inf}, OIIO::TypeDesc::HALF),
      {"texel (1, 1) channel 0 is infinite"});
  expect_refused(
      "neg.exr",
      encode_image("neg.exr", 2, 2, 1, std::vector<float>{0, -0.5f, 0, 0}, OIIO::TypeDesc::FLOAT),
      {"texel (1, 0) channel 0 is negative"});
  expect_refused("junk.png", "this is not a PNG file", {"cannot decode image"});
  expect_refused("empty.exr", "", {"cannot decode image"});
  try {
    TextureSet set({bitmap("missing.png")}, memory_reader({}));
    FAIL() << "accepted a missing file";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "textures[0]: missing.png: no such file in the bundle");
  }
}

struct MitsubaLookup {
  int config;
  float u, v, r, g, b, eval_1, du, dv;
};

/// Lookups by Mitsuba 3 itself (worker/render/texture/mitsuba_reference.py), over the same
/// images as these tests make.
const MitsubaLookup kMitsubaLookups[] = {
#include "mitsuba_reference.inc"
};

/// The configurations of mitsuba_reference.py's CONFIGS, in its order.
std::vector<Texture> mitsuba_reference_textures() {
  glm::dmat3 to_uv(1.0);
  to_uv[0][0] = 2;    // u' = 2 u + 0.1
  to_uv[1][1] = 0.5;  // v' = v / 2 + 0.2
  to_uv[2][0] = 0.1;
  to_uv[2][1] = 0.2;
  using W = TextureWrap;
  using F = TextureFilter;
  Texture scaled = bitmap("rgb8.png");
  scaled.to_uv = to_uv;
  Texture checker;
  checker.kind = TextureKind::checkerboard;
  Texture checker_scaled = checker;
  checker_scaled.to_uv = to_uv;
  return {bitmap("rgb8.png", W::repeat),
          bitmap("rgb8.png", W::mirror),
          bitmap("rgb8.png", W::clamp),
          bitmap("rgb8.png", W::repeat, F::nearest),
          bitmap("rgb8.png", W::mirror, F::nearest),
          bitmap("rgb8.png", W::clamp, F::nearest),
          bitmap("rgb8.png", W::repeat, F::bilinear, TextureColorSpace::linear),
          bitmap("wrap.exr", W::repeat),
          bitmap("wrap.exr", W::mirror),
          bitmap("y16.png", W::clamp),
          scaled,
          checker,
          checker_scaled};
}

/// Agreement to rounding: Mitsuba approximates the sRGB curve (to 4e-7) and fuses
/// multiply-adds; gradients scale texel differences by the resolution.
TEST(TextureSet, MatchesMitsubaLookups) {
  std::map<std::string, std::string> files = test_files();
  files["y16.png"] = encode_image("y16.png", 2, 2, 1, std::vector<uint16_t>{0, 32768, 65535, 1000},
                                  OIIO::TypeDesc::UINT16);
  const TextureSet set(mitsuba_reference_textures(), memory_reader(files));
  const auto close = [](float a, float b, float rel) {
    return std::abs(a - b) <= rel * std::max(1.0f, std::abs(b));
  };
  int compared = 0;
  for (const MitsubaLookup& m : kMitsubaLookups) {
    const glm::vec2 uv(m.u, m.v);
    const glm::vec3 c = set.lookup(m.config, uv);
    const std::string where = "config " + std::to_string(m.config) + " uv " + std::to_string(m.u) +
                              "," + std::to_string(m.v);
    EXPECT_TRUE(close(c.x, m.r, 2e-6f) && close(c.y, m.g, 2e-6f) && close(c.z, m.b, 2e-6f))
        << where << ": " << c.x << " " << c.y << " " << c.z << " vs " << m.r << " " << m.g << " "
        << m.b;
    if (m.config >= 11)
      continue;  // checkerboards: Mitsuba's eval_1 swaps the colours (texture/checkerboard.h)
    EXPECT_TRUE(close(set.lookup_1(m.config, uv), m.eval_1, 2e-6f))
        << where << ": " << set.lookup_1(m.config, uv) << " vs " << m.eval_1;
    const glm::vec2 g = set.gradient(m.config, uv);
    EXPECT_TRUE(close(g.x, m.du, 1e-5f) && close(g.y, m.dv, 1e-5f))
        << where << ": " << g.x << " " << g.y << " vs " << m.du << " " << m.dv;
    ++compared;
  }
  EXPECT_EQ(compared, 11 * 16);
}

/// The sRGB decoding of 8- and 16-bit codes uses libm's pow, which may round differently on
/// machines with other instruction sets. It cannot change a texel: for every 8-bit code the
/// stored float, and for every 16-bit code the stored half, is the same for any value within
/// 1e-12 (relative) of the decoded one, far more than pow's error of an ulp or two (1e-16).
TEST(TextureSet, SrgbDecodingIsImmuneToLibmRounding) {
  int unstable = 0;
  for (int code = 0; code <= 255; ++code) {
    const double v = srgb_to_linear(code / 255.0);
    if (float(v * (1 - 1e-12)) != float(v) || float(v * (1 + 1e-12)) != float(v)) ++unstable;
  }
  for (int code = 0; code <= 65535; ++code) {
    const double v = srgb_to_linear(code / 65535.0);
    const float lo = half_of(v * (1 - 1e-12)), mid = half_of(v), hi = half_of(v * (1 + 1e-12));
    if (lo != mid || hi != mid) ++unstable;
  }
  EXPECT_EQ(unstable, 0);
}

}  // namespace
}  // namespace tessera
