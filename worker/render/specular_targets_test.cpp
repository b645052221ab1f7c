// Specular targets (specular_targets.h): which shapes become targets, their bounding spheres, the
// mixture's sampling against its pdf (chi-square), its normalisation, and a glass scene rendered
// with and without the mixture agreeing in its mean.
#include "render/guiding/target_mixture.h"

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "render/bsdf/chi_square.h"
#include "render/renderer.h"
#include "render/scene/traceable_scene.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

const std::string kSource = TESSERA_SOURCE_DIR;


/// A mixture at the origin with normal +z, through the chi-square harness's BSDF interface:
/// u_lobe picks the strategy, u the direction; wo is unused.
struct MixtureAsBsdf {
  TargetMixture mix;
  std::optional<BsdfSample> sample(glm::vec3, float u_lobe, glm::vec2 u) const {
    const int cone = mix.choose(u_lobe);
    BsdfSample s;
    s.wi = cone < 0 ? square_to_cosine_hemisphere(u) : mix.sample_cone(cone, u);
    s.pdf = mix.pdf(s.wi, s.wi.z, cone);
    return s;
  }
  float pdf(glm::vec3, glm::vec3 wi) const { return mix.pdf(wi, wi.z); }
};

/// Targets from spheres given directly (centre, radius) in a scene of radius 100.
SpecularTargets targets_of(const std::vector<SpecularTarget>& spheres) {
  std::vector<std::unique_ptr<Geometry>> geometries;
  std::vector<SpecularTargets::ShapeRef> refs;
  std::vector<RenderMaterial> materials(1);
  materials[0].type = MaterialType::glass;
  for (const SpecularTarget& t : spheres) {
    auto g = std::make_unique<Geometry>();
    g->kind = Geometry::Kind::sphere;
    g->center = glm::dvec3(t.center);
    g->radius = t.radius;
    refs.push_back({g.get(), nullptr});
    geometries.push_back(std::move(g));
  }
  return SpecularTargets(refs, materials, 100.0f);
}

/// Beside (at the horizon), above, and partly below the horizon of normal +z at the origin.
std::vector<SpecularTarget> three_spheres() {
  return {{{2.0f, 0.0f, 0.3f}, 0.9f}, {{0.4f, 0.3f, 2.0f}, 1.0f}, {{-1.0f, 1.5f, 0.3f}, 0.8f}};
}

double integrate_pdf(const TargetMixture& mix, float z_min);

/// A scene's worth of targets with lamps: glass and mirror spheres, flat mirror triangles and
/// spherical lamps, given directly (materials: 0 glass of IOR 1.5, 1 a diffuse lamp, 2 mirror).
struct LampScene {
  std::vector<std::unique_ptr<Geometry>> geometries;
  std::vector<SpecularTargets::ShapeRef> refs;
  std::vector<RenderMaterial> materials = std::vector<RenderMaterial>(3);
  LampScene() {
    materials[0].type = MaterialType::glass;
    materials[0].ior = 1.5f;
    materials[2].type = MaterialType::mirror;
  }
  Geometry& add_sphere(glm::vec3 center, float radius, uint32_t material) {
    auto g = std::make_unique<Geometry>();
    g->kind = Geometry::Kind::sphere;
    g->center = glm::dvec3(center);
    g->radius = radius;
    g->material = material;
    refs.push_back({g.get(), nullptr});
    geometries.push_back(std::move(g));
    return *geometries.back();
  }
  void add_lamp(glm::vec3 center, float radius) { add_sphere(center, radius, 1).emission = glm::vec3(10.0f); }
  void add_mirror_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    auto g = std::make_unique<Geometry>();
    g->positions = {a, b, c};
    g->indices = {glm::u32vec3(0, 1, 2)};
    g->material = 2;
    refs.push_back({g.get(), nullptr});
    geometries.push_back(std::move(g));
  }
  SpecularTargets targets() const { return SpecularTargets(refs, materials, 100.0f); }
};

/// Seen from the origin with normal +z: a glass sphere above with a lamp beyond it (a real
/// image between the point and the lens), a mirror sphere to the side lit from above, and a
/// flat mirror triangle facing a second lamp.
LampScene lamps_glass_and_mirrors() {
  LampScene s;
  s.add_sphere({0.3f, 0.0f, 2.0f}, 0.5f, 0);
  s.add_lamp({0.6f, 0.2f, 6.0f}, 0.3f);
  s.add_sphere({-1.5f, 0.5f, 0.8f}, 0.4f, 2);
  s.add_lamp({-2.5f, 1.0f, 4.0f}, 0.2f);
  s.add_mirror_triangle({1.5f, -1.0f, 0.2f}, {1.5f, 1.0f, 0.2f}, {1.8f, 0.0f, 1.6f});
  return s;
}

TEST(SpecularTargets, LampImagesAreSampledByTheirPdf) {
  const LampScene scene = lamps_glass_and_mirrors();
  const SpecularTargets targets = scene.targets();
  ASSERT_EQ(targets.size(), 3);
  ASSERT_GE(targets.image_count(), 3);
  MixtureAsBsdf m;
  ASSERT_TRUE(m.mix.init(targets, glm::vec3(0.0f), glm::vec3(0, 0, 1)));
  // The glass's, the mirror sphere's and at least one image cone.
  ASSERT_GE(m.mix.count(), 4);
  const test::ChiSquareResult r = test::chi_square_test(m, glm::vec3(0, 0, 1), 11, 400000, 0.01);
  EXPECT_TRUE(r.passed) << r.message;
  // A tilted normal: cones partly below the horizon.
  MixtureAsBsdf tilted;
  ASSERT_TRUE(tilted.mix.init(targets, glm::vec3(0.0f), glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f))));
  const test::ChiSquareResult rt = test::chi_square_test(tilted, glm::vec3(0, 0, 1), 12, 400000, 0.01);
  EXPECT_TRUE(rt.passed) << rt.message;
}

TEST(SpecularTargets, PdfWithLampImagesIntegratesToOne) {
  const LampScene scene = lamps_glass_and_mirrors();
  const SpecularTargets targets = scene.targets();
  TargetMixture mix;
  ASSERT_TRUE(mix.init(targets, glm::vec3(0.0f), glm::vec3(0, 0, 1)));
  ASSERT_GE(mix.count(), 4);
  // Every cone's centre is above the horizon, but a cone may reach below it: the whole sphere.
  EXPECT_NEAR(integrate_pdf(mix, -2.0f), 1.0, 2e-3);
}

TEST(SpecularTargets, BallLensImageByGaussianOptics) {
  // n = 1.5, R = 0.5: f = 0.75. Lamp at distance 4 on +z: d_i = 0.75 * 4 / 3.25.
  const glm::vec3 c(0.0f, 0.0f, 2.0f), lamp(0.0f, 0.0f, 6.0f);
  const auto real = ball_lens_image(c, 0.5f, 1.5f, lamp, 0.3f);
  ASSERT_TRUE(real);
  const float d_i = 0.75f * 4.0f / 3.25f;
  EXPECT_NEAR(real->center.z, 2.0f - d_i, 1e-5f);
  EXPECT_NEAR(real->radius, d_i / 4.0f * 0.3f + SpecularTargets::kLensAberration * 0.5f, 1e-5f);
  // The gate: the far side of the lens's centre from the lamp.
  EXPECT_GT(glm::dot(real->gate_normal, glm::vec3(0.0f)), real->gate_offset);
  EXPECT_LT(glm::dot(real->gate_normal, glm::vec3(0.0f, 0.0f, 4.0f)), real->gate_offset);
  // Inside the focal length (d = 0.6 < f): a virtual image on the lamp's side, beyond the lamp.
  const auto virt = ball_lens_image(c, 0.5f, 1.5f, c + glm::vec3(0.0f, 0.0f, 0.6f), 0.05f);
  ASSERT_TRUE(virt);
  EXPECT_GT(virt->center.z, 2.6f);
  EXPECT_TRUE(std::isfinite(virt->radius));
  // At the focal distance: the image at infinity, none.
  EXPECT_FALSE(ball_lens_image(c, 0.5f, 1.5f, c + glm::vec3(0.0f, 0.75f, 0.0f), 0.05f));
  // IOR 1: the lamp itself.
  const auto same = ball_lens_image(c, 0.5f, 1.0f, lamp, 0.3f);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->center, lamp);
  EXPECT_EQ(same->radius, 0.3f);
  // The lamp inside the lens, or on its centre: none.
  EXPECT_FALSE(ball_lens_image(c, 0.5f, 1.5f, c + glm::vec3(0.1f, 0.0f, 0.0f), 0.05f));
  EXPECT_FALSE(ball_lens_image(c, 0.5f, 1.5f, c, 0.05f));
}

TEST(SpecularTargets, MirrorImages) {
  // Convex mirror R = 1 at the origin, lamp at distance 3 on +y: object distance 2 from the
  // vertex, f = -0.5, d_i = -0.5 * 2 / 2.5 = -0.4: the image at y = 1 - 0.4.
  const auto convex = convex_mirror_image(glm::vec3(0.0f), 1.0f, {0.0f, 3.0f, 0.0f}, 0.2f);
  ASSERT_TRUE(convex);
  EXPECT_NEAR(convex->center.y, 0.6f, 1e-5f);
  EXPECT_NEAR(convex->radius, 0.2f * 0.4f / 2.0f + SpecularTargets::kMirrorAberration, 1e-5f);
  EXPECT_FALSE(convex_mirror_image(glm::vec3(0.0f), 1.0f, {0.0f, 0.5f, 0.0f}, 0.2f));  // lamp inside
  // A flat face in the plane z = 0: the lamp mirrored through it, the same radius; the gate is
  // the lamp's side, whichever way the face winds.
  const std::vector<glm::vec3> face = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
  const auto flat = flat_mirror_image(face, glm::vec3(0.2f, 0.2f, -0.5f), {0.3f, 0.4f, 2.0f}, 0.25f);
  ASSERT_TRUE(flat);
  EXPECT_EQ(flat->center, glm::vec3(0.3f, 0.4f, -2.0f));
  EXPECT_EQ(flat->radius, 0.25f);
  EXPECT_GT(glm::dot(flat->gate_normal, glm::vec3(0.0f, 0.0f, 1.0f)), flat->gate_offset);
  // Seen from inside the shape the face bounds (the lamp on the inner side): none.
  EXPECT_FALSE(flat_mirror_image(face, glm::vec3(0.2f, 0.2f, 0.5f), {0.3f, 0.4f, 2.0f}, 0.25f));
  // The lamp's centre on the plane, a degenerate face: none.
  EXPECT_FALSE(flat_mirror_image(face, glm::vec3(0.2f, 0.2f, -0.5f), {3.0f, 4.0f, 0.0f}, 0.25f));
  EXPECT_FALSE(flat_mirror_image({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, glm::vec3(0.0f, 0.0f, -1.0f), {0.0f, 0.0f, 2.0f}, 0.25f));
}

TEST(SpecularTargets, ImageConesOnlyWhereTheTargetCarriesTheLamp) {
  // A lens at z = 2, its lamp at z = 6: the image cone exists below the lens (gate), points
  // toward the lens (the real image beyond the point: aimed at 2p - I), and not above it.
  LampScene s;
  s.add_sphere({0.0f, 0.0f, 2.0f}, 0.5f, 0);
  s.add_lamp({0.0f, 0.0f, 6.0f}, 0.3f);
  const SpecularTargets targets = s.targets();
  ASSERT_EQ(targets.image_count(), 1);
  const SpecularImage& image = targets.images()[0];
  ASSERT_LT(image.center.z + image.radius, 1.4f);
  ASSERT_GT(image.center.z, 0.5f);
  TargetMixture mix;
  // Between the lens (z >= 1.5) and the image: two cones, the image's axis toward the lens (+z).
  const glm::vec3 between(0.0f, 0.0f, 1.45f);
  ASSERT_TRUE(mix.init(targets, between, glm::vec3(0, 0, 1)));
  EXPECT_EQ(mix.count(), 2);
  // Far off to the side, the line through the image misses the lens: only the bounding cone.
  ASSERT_TRUE(mix.init(targets, glm::vec3(4.0f, 0.0f, 0.0f), glm::normalize(glm::vec3(-1, 0, 1))));
  EXPECT_EQ(mix.count(), 1);
  // On the lamp's side of the lens, facing it: only the bounding cone.
  ASSERT_TRUE(mix.init(targets, glm::vec3(0.5f, 0.0f, 3.0f), glm::vec3(0, 0, -1)));
  EXPECT_EQ(mix.count(), 1);
  // Inside the image's sphere: none of it.
  ASSERT_TRUE(mix.init(targets, image.center, glm::vec3(0, 0, 1)));
  EXPECT_EQ(mix.count(), 1);
  // Below the image the cone aims at the image itself, again toward the lens.
  ASSERT_TRUE(mix.init(targets, glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0, 0, 1)));
  EXPECT_EQ(mix.count(), 2);
  // Directions sampled from the image cone of a point between the lens and the image point up,
  // toward the lens, with a finite pdf.
  ASSERT_TRUE(mix.init(targets, between, glm::vec3(0, 0, 1)));
  std::mt19937_64 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 w = mix.sample_cone(1, {test::u01(rng), test::u01(rng)});
    EXPECT_GT(w.z, 0.8f);
    EXPECT_TRUE(std::isfinite(mix.pdf(w, w.z, 1)));
  }
}

TEST(SpecularTargets, MixtureSamplesItsPdf) {
  const std::vector<SpecularTarget> spheres = three_spheres();
  int tests = 0;
  uint64_t seed = 7;
  // Each sphere alone, then all three.
  for (int i = 0; i <= 3; ++i) {
    const std::vector<SpecularTarget> chosen =
        i < 3 ? std::vector<SpecularTarget>{spheres[size_t(i)]} : spheres;
    const SpecularTargets targets = targets_of(chosen);
    MixtureAsBsdf m;
    ASSERT_TRUE(m.mix.init(targets, glm::vec3(0.0f), glm::vec3(0, 0, 1)));
    ASSERT_EQ(m.mix.count(), int(chosen.size()));
    const test::ChiSquareResult r = test::chi_square_test(m, glm::vec3(0, 0, 1), seed++, 200000, 0.01 / 4);
    EXPECT_TRUE(r.passed) << "case " << i << ": " << r.message;
    ++tests;
  }
  EXPECT_EQ(tests, 4);
}

/// The integral of pdf over directions with z > z_min, by the midpoint rule on a fine
/// (theta, phi) grid.
double integrate_pdf(const TargetMixture& mix, float z_min) {
  constexpr int kTheta = 1200, kPhi = 2400;
  const double dtheta = kPi / kTheta, dphi = 2 * kPi / kPhi;
  double sum = 0;
  for (int a = 0; a < kTheta; ++a) {
    const double theta = (a + 0.5) * dtheta;
    double ring = 0;
    for (int b = 0; b < kPhi; ++b) {
      const glm::vec3 w = test::spherical(float(theta), float((b + 0.5) * dphi));
      if (w.z > z_min) ring += mix.pdf(w, w.z);
    }
    sum += ring * std::sin(theta);
  }
  return sum * dtheta * dphi;
}

TEST(SpecularTargets, PdfIntegratesToOne) {
  // Cones above the horizon: 1 over the hemisphere. With one partly below: 1 over the sphere
  // (the cone's lower part is where its samples go below the surface, weight 0).
  const std::vector<SpecularTarget> spheres = three_spheres();
  TargetMixture above;
  ASSERT_TRUE(above.init(targets_of({spheres[1], {{-1.5f, -1.0f, 1.2f}, 0.3f}}), glm::vec3(0.0f),
                         glm::vec3(0, 0, 1)));
  EXPECT_NEAR(integrate_pdf(above, 0.0f), 1.0, 2e-3);
  TargetMixture all;
  ASSERT_TRUE(all.init(targets_of(spheres), glm::vec3(0.0f), glm::vec3(0, 0, 1)));
  EXPECT_NEAR(integrate_pdf(all, -2.0f), 1.0, 2e-3);
}

TEST(SpecularTargets, NoConeForASphereHoldingThePointOrBelowTheHorizon) {
  const glm::vec3 n(0, 0, 1);
  TargetMixture mix;
  // The point inside: no cone.
  EXPECT_FALSE(mix.init(targets_of({{{0.2f, 0.0f, 0.1f}, 0.5f}}), glm::vec3(0.0f), n));
  // Wholly below the horizon, or its centre below it: none either.
  EXPECT_FALSE(mix.init(targets_of({{{0.0f, 1.0f, -2.0f}, 0.5f}}), glm::vec3(0.0f), n));
  EXPECT_FALSE(mix.init(targets_of({{{0.0f, 2.0f, -0.1f}, 0.5f}}), glm::vec3(0.0f), n));
  // One inside, one outside: only the outside one is sampled, never a direction toward the
  // sphere holding the point other than through the cosine strategy's hemisphere.
  const SpecularTarget inside{{0.0f, 0.0f, 0.2f}, 0.5f}, outside{{1.5f, 0.0f, 1.0f}, 0.8f};
  ASSERT_TRUE(mix.init(targets_of({inside, outside}), glm::vec3(0.0f), n));
  ASSERT_EQ(mix.count(), 1);
  std::mt19937_64 rng(3);
  const glm::vec3 axis = glm::normalize(outside.center);
  const float cos_max = std::sqrt(1.0f - outside.radius * outside.radius / glm::dot(outside.center, outside.center));
  int cone_samples = 0;
  for (int i = 0; i < 10000; ++i) {
    const float u_strategy = test::u01(rng);
    const glm::vec2 u(test::u01(rng), test::u01(rng));
    const int cone = mix.choose(u_strategy);
    if (cone < 0) continue;
    ++cone_samples;
    EXPECT_EQ(cone, 0);
    EXPECT_GE(glm::dot(mix.sample_cone(cone, u), axis), cos_max - 1e-5f);
  }
  EXPECT_GT(cone_samples, 1000);  // p = 0.23 here
}

TEST(SpecularTargets, BoundingSphereHoldsEveryPointAndIsTight) {
  // Points on a unit sphere around (1, 2, 3): Ritter's sphere is within 5 % of it.
  std::vector<glm::vec3> points;
  for (int a = 1; a < 20; ++a) {
    for (int b = 0; b < 40; ++b) {
      points.push_back(glm::vec3(1, 2, 3) + test::spherical(kPi * a / 20, 2 * kPi * b / 40));
    }
  }
  const SpecularTarget s = bounding_sphere(points);
  for (const glm::vec3& p : points) EXPECT_LE(glm::length(p - s.center), s.radius);
  EXPECT_LT(s.radius, 1.05f);
  // A cube's corners: the box's sphere.
  std::vector<glm::vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back({(i & 1) ? 1.f : -1.f, (i & 2) ? 1.f : -1.f, (i & 4) ? 1.f : -1.f});
  const SpecularTarget c = bounding_sphere(corners);
  for (const glm::vec3& p : corners) EXPECT_LE(glm::length(p - c.center), c.radius);
  EXPECT_NEAR(c.radius, std::sqrt(3.0f), 1e-5f);
}

TEST(SpecularTargets, TheBenchmarkScenesTargetTheirGlassAndMirrors) {
  struct Case {
    const char* file;
    int targets;
  };
  // hexroom: the mirror sphere, the glass sphere, the mirror tetrahedron; cornell-sphere: its
  // mirror and glass spheres (meshes); the Cornell box: none.
  // Lamp images: hexroom's three lamps through the glass sphere, in the mirror sphere and in
  // the tetrahedron's faces, more than kMaxImages; cornell-sphere's one lamp in each sphere.
  struct Images {
    const char* file;
    int images;
  };
  for (const Case c : {Case{"hexroom.json", 3}, Case{"cornell-sphere.json", 2}, Case{"cornell.json", 0}}) {
    const TraceableScene scene(load_scene_file(kSource + "/scenes/" + c.file), 16, 16, "");
    EXPECT_EQ(scene.specular_targets().size(), c.targets) << c.file;
  }
  for (const Images c : {Images{"hexroom.json", SpecularTargets::kMaxImages}, Images{"cornell-sphere.json", 2},
                         Images{"cornell.json", 0}}) {
    const TraceableScene scene(load_scene_file(kSource + "/scenes/" + c.file), 16, 16, "");
    EXPECT_EQ(scene.specular_targets().image_count(), c.images) << c.file;
  }
  const SpecularTargets::DisabledForTest off;
  const TraceableScene scene(load_scene_file(kSource + "/scenes/hexroom.json"), 16, 16, "");
  EXPECT_TRUE(scene.specular_targets().empty());
}

TEST(SpecularTargets, ASphereAroundTheWholeSceneIsNoTarget) {
  Scene s;
  const uint32_t white = test::add_diffuse(s, {0.5, 0.5, 0.5});
  const uint32_t glass = test::add_material(s, MaterialType::glass);
  s.shapes.push_back(test::quad({-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, white));
  s.shapes.push_back(test::sphere({0, 0, 0}, 5, glass));
  s.shapes.push_back(test::sphere({0, 0.5, 0}, 0.2, glass));
  s.camera.position = {0, 1, 3};
  s.camera.look_at = {0, 0, 0};
  const TraceableScene scene(s, 8, 8, "");
  ASSERT_EQ(scene.specular_targets().size(), 1);
  EXPECT_NEAR(scene.specular_targets()[0].radius, 0.2f, 1e-6f);
}

TEST(SpecularTargets, GlassSceneMeanIsTheSameWithAndWithoutTheMixture) {
  // cornell-sphere, small: the mixture changes which directions diffuse points sample, never the
  // expected image. Compared per 8x8 block (the caustic under the glass sphere, what the mirror
  // shows) and as a whole, each within 5 standard errors.
  const Scene s = load_scene_file(kSource + "/scenes/cornell-sphere.json");
  constexpr int kSize = 32, kBlock = 8;
  const uint32_t spp = 256;
  const auto render = [&](bool mixture) {
    std::optional<SpecularTargets::DisabledForTest> off;
    if (!mixture) off.emplace();
    const Renderer renderer(s, test::test_job(kSize, kSize, spp));
    return renderer.render({0, 0, kSize, kSize}, 0, spp);
  };
  const Accumulation with = render(true), without = render(false);
  EXPECT_TRUE(test::all_finite(with));
  const test::Estimate ew = test::mean_luminance(with), eo = test::mean_luminance(without);
  std::printf("with the mixture %.6f (SE %.1e), without %.6f (SE %.1e)\n", ew.mean, ew.se, eo.mean, eo.se);
  EXPECT_NEAR(ew.mean, eo.mean, test::tolerance(ew, eo));
  for (const std::string& block : test::differing_blocks(with, without, kSize, kBlock)) ADD_FAILURE() << block;
}

/// The mixture's cones by the per-cone scalar loop TargetMixture::init had before it went four
/// lanes at a time: the specification its lanes must match bit for bit.
struct ScalarMixture {
  struct Cone {
    glm::vec3 axis;
    float one_minus_cos, cos_max, cdf, density;
  };
  std::vector<Cone> cones;
  float p_cosine = 1;

  void add(glm::vec3 d, float inv_dist, float one_minus_cos, float cos_axis, float mass, float q,
           std::vector<std::pair<float, float>>* mass_cos_q) {
    cones.push_back({d * inv_dist, one_minus_cos, 1.0f - one_minus_cos, 0, 0});
    mass_cos_q->push_back({mass * cos_axis, q});
  }

  bool init(const SpecularTargets& targets, glm::vec3 p, glm::vec3 n) {
    cones.clear();
    std::vector<std::pair<float, float>> mass_cos_q;
    float sum_p = 0;
    for (int i = 0; i < targets.size(); ++i) {
      const SpecularTarget s = targets[i];
      const glm::vec3 d = s.center - p;
      const float dn = glm::dot(d, n);
      if (!(dn > 0)) continue;
      const float dist2 = glm::dot(d, d);
      const float r2 = targets.lanes().r2[i];
      if (!(dist2 > r2)) continue;
      const float inv_dist = 1.0f / std::sqrt(dist2);
      const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
      const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
      const float cos_axis = dn * inv_dist;
      const float q = SpecularTargets::kMassFactor * (2.0f * one_minus_cos * cos_axis);
      if (!(q > 0)) continue;
      add(d, inv_dist, one_minus_cos, cos_axis, SpecularTargets::kMassFactor, q, &mass_cos_q);
      sum_p += q;
    }
    for (int j = 0; j < targets.image_count(); ++j) {
      const SpecularImage& im = targets.images()[j];
      if (!(glm::dot(im.gate_normal, p) > im.gate_offset)) continue;
      glm::vec3 d = im.center - p;
      const glm::vec3 e = im.window_center - p;
      if (glm::dot(d, e) < 0) d = -d;
      const float dn = glm::dot(d, n);
      if (!(dn > 0)) continue;
      const float dist2 = glm::dot(d, d);
      const float r2 = im.radius * im.radius;
      if (!(dist2 > r2)) continue;
      const float inv_dist = 1.0f / std::sqrt(dist2);
      const float t = glm::dot(e, d) * inv_dist;
      const float reach = im.window_radius + im.radius * t * inv_dist;
      if (!(glm::dot(e, e) - t * t <= reach * reach)) continue;
      const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
      const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
      const float cos_axis = dn * inv_dist;
      const float q = SpecularTargets::kImageMassFactor * (2.0f * one_minus_cos * cos_axis);
      if (!(q > 0)) continue;
      add(d, inv_dist, one_minus_cos, cos_axis, SpecularTargets::kImageMassFactor, q, &mass_cos_q);
      sum_p += q;
    }
    if (cones.empty()) return false;
    const float scale =
        sum_p > SpecularTargets::kMaxTargetProbability ? SpecularTargets::kMaxTargetProbability / sum_p : 1.0f;
    float cdf = 0;
    for (size_t k = 0; k < cones.size(); ++k) {
      cdf += mass_cos_q[k].second * scale;
      cones[k].cdf = cdf;
      cones[k].density = mass_cos_q[k].first * (kInvPi * scale);
    }
    p_cosine = 1.0f - cdf;
    return true;
  }

  int choose(float u) const {
    if (u >= cones.back().cdf) return -1;
    for (size_t k = 0; k + 1 < cones.size(); ++k) {
      if (u < cones[k].cdf) return int(k);
    }
    return int(cones.size()) - 1;
  }

  float pdf(glm::vec3 w, float cos_n, int sampled_cone) const {
    float pdf = cos_n > 0 ? p_cosine * (cos_n * kInvPi) : 0.0f;
    for (size_t k = 0; k < cones.size(); ++k) {
      if (int(k) == sampled_cone || glm::dot(w, cones[k].axis) >= cones[k].cos_max) pdf += cones[k].density;
    }
    return pdf;
  }
};

uint32_t bits_of(float x) {
  uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// Eight lanes, as the AVX2 and AVX-512 kernels' init_mixture takes them (here in baseline code:
/// the same lane-wise operations, whatever instructions carry them).
using Float8 = float __attribute__((vector_size(32)));
using Mask8 = int32_t __attribute__((vector_size(32)));

/// Compares TargetMixture with ScalarMixture at `points` random points of the box [lo, hi]
/// with random normals: the same cones (count, choice of each u, directions sampled in each)
/// and the same pdf bits for sampled and random directions, with four lanes (init) and with
/// eight (init_lanes). Returns the cones seen in all.
int expect_same_as_scalar(const SpecularTargets& targets, glm::vec3 lo, glm::vec3 hi, int points, uint64_t seed) {
  std::mt19937_64 rng(seed);
  int cones = 0;
  for (int i = 0; i < 2 * points; ++i) {
    const glm::vec3 p = lo + (hi - lo) * glm::vec3(test::u01(rng), test::u01(rng), test::u01(rng));
    const glm::vec3 n = square_to_uniform_sphere(glm::vec2(test::u01(rng), test::u01(rng)));
    TargetMixture lanes;
    ScalarMixture scalar;
    const bool any = i % 2 == 0 ? lanes.init(targets, p, n) : lanes.init_lanes<Float8, Mask8>(targets, p, n);
    EXPECT_EQ(any, scalar.init(targets, p, n)) << "point " << i;
    if (!any) continue;
    EXPECT_EQ(lanes.count(), int(scalar.cones.size())) << "point " << i;
    if (lanes.count() != int(scalar.cones.size())) return cones;
    cones += lanes.count();
    for (int k = 0; k < lanes.count(); ++k) {
      // u just below and at cone k's cdf: the same strategy.
      const float cdf = scalar.cones[size_t(k)].cdf;
      for (const float u : {std::nextafter(cdf, 0.0f), cdf}) {
        EXPECT_EQ(lanes.choose(u), scalar.choose(u)) << "point " << i << " cone " << k;
      }
      const glm::vec2 u(test::u01(rng), test::u01(rng));
      const glm::vec3 w = lanes.sample_cone(k, u);
      const ScalarMixture::Cone& c = scalar.cones[size_t(k)];
      const glm::vec2 disk = square_to_concentric_disk(u);
      const float omc = glm::dot(disk, disk) * c.one_minus_cos;
      const float s = std::sqrt(std::max(0.0f, c.one_minus_cos * (2.0f - omc)));
      const glm::vec3 expected = Frame(c.axis).to_world(glm::vec3(disk.x * s, disk.y * s, 1.0f - omc));
      for (int a = 0; a < 3; ++a) EXPECT_EQ(bits_of(w[a]), bits_of(expected[a])) << "point " << i << " cone " << k;
      const float cos_n = glm::dot(w, n);
      EXPECT_EQ(bits_of(lanes.pdf(w, cos_n, k)), bits_of(scalar.pdf(w, cos_n, k))) << "point " << i << " cone " << k;
      EXPECT_EQ(bits_of(lanes.pdf(w, cos_n)), bits_of(scalar.pdf(w, cos_n, -1))) << "point " << i << " cone " << k;
    }
    for (int j = 0; j < 8; ++j) {
      const glm::vec3 w = square_to_uniform_sphere(glm::vec2(test::u01(rng), test::u01(rng)));
      const float cos_n = glm::dot(w, n);
      EXPECT_EQ(bits_of(lanes.pdf(w, cos_n)), bits_of(scalar.pdf(w, cos_n, -1))) << "point " << i;
    }
  }
  return cones;
}

// TargetMixture's append (eight lanes in the AVX2 and AVX-512 kernels) stores a block's kept
// cones with float4::compress_store: every set of lanes lands at the front, in lane order, and
// nothing before `out` is written.
TEST(SpecularTargets, CompressStoreKeepsTheChosenLanesInLaneOrder) {
  const Float8 v = {10, 11, 12, 13, 14, 15, 16, 17};
  for (unsigned bits = 0; bits < 256; ++bits) {
    float out[1 + 8];
    std::fill(std::begin(out), std::end(out), -1.0f);
    float4::compress_store<Float8, Mask8>(out + 1, v, bits);
    EXPECT_EQ(out[0], -1.0f) << "bits " << bits;
    int k = 1;
    for (int l = 0; l < 8; ++l) {
      if (bits & (1u << l)) {
        EXPECT_EQ(out[k++], v[l]) << "bits " << bits << " lane " << l;
      }
    }
  }
}

TEST(SpecularTargets, ConesFourAtATimeAreTheScalarLoopsBits) {
  // The benchmark scenes' own targets and images (hexroom: 3 targets and 8 images, more than a
  // block: the targets' formula, then the images'; cornell-sphere: 2 and 2, one block through
  // the images' formula), at points over their rooms.
  struct Case {
    const char* file;
    glm::vec3 lo, hi;
  };
  for (const Case& c :
       {Case{"hexroom.json", {-5, 0, -5}, {5, 4, 5}}, Case{"cornell-sphere.json", {-1, 0, -1}, {1, 2, 1}}}) {
    const TraceableScene scene(load_scene_file(kSource + "/scenes/" + c.file), 16, 16, "");
    const int cones = expect_same_as_scalar(scene.specular_targets(), c.lo, c.hi, 3000, 7);
    EXPECT_GT(cones, 3000) << c.file;  // many points see several cones
  }
  // Glass and mirror spheres, a flat mirror and two lamps, around the origin.
  const LampScene lamps = lamps_glass_and_mirrors();
  EXPECT_GT(expect_same_as_scalar(lamps.targets(), glm::vec3(-3.0f), glm::vec3(3.0f), 3000, 8), 3000);
  // Nine targets (one more than kMaxTargets: two blocks, the second full).
  std::vector<SpecularTarget> nine;
  for (int i = 0; i < 9; ++i) nine.push_back({{float(i % 3) * 2 - 2, float(i / 3) * 2 - 2, 2.0f}, 0.3f + 0.05f * i});
  EXPECT_GT(expect_same_as_scalar(targets_of(nine), glm::vec3(-3.0f), glm::vec3(3.0f), 3000, 9), 3000);
}

}  // namespace
}  // namespace tessera
