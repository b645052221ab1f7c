// Principled (and thin principled, pplastic, blend) materials through the whole renderer:
// spheres of every lobe (opaque, metallic, transmissive, two-sided) inside a constant
// environment render without NaN or Inf, and the energy-conserving ones show at most the
// environment's radiance (a lossless one exactly it).
#include <gtest/gtest.h>

#include "accum/film.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

/// A principled sphere of radius 1 at the origin seen from (0, 0, 4) inside a constant
/// environment of radiance `le`.
Scene principled_sphere(const PrincipledParameters& params, glm::dvec3 base_color, double le) {
  Scene s;
  s.camera.position = {0, 0, 4};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 30;
  Material m;
  m.name = "principled";
  m.type = MaterialType::principled;
  m.reflectance.value = base_color;
  m.principled = params;
  s.materials.push_back(m);
  s.shapes.push_back(test::sphere({0, 0, 0}, 1, 0));
  Light sky;
  sky.kind = LightKind::constant;
  sky.value = glm::dvec3(le);
  s.lights.push_back(sky);
  return s;
}

TEST(PrincipledRender, EveryLobeRendersFinite) {
  std::vector<PrincipledParameters> cases(4);
  cases[1].metallic = {1, -1};
  cases[1].anisotropic = {0.8, -1};
  cases[1].roughness = {0, -1};
  cases[2].spec_trans = {1, -1};
  cases[2].roughness = {0.2, -1};
  cases[3].sheen = cases[3].clearcoat = cases[3].flatness = {1, -1};
  cases[3].clearcoat_gloss = {1, -1};
  cases[3].spec_trans = {0.5, -1};
  for (size_t i = 0; i < cases.size(); ++i) {
    const Renderer renderer(principled_sphere(cases[i], {0.8, 0.5, 0.2}, 1.0),
                            test::test_job(24, 24, 8));
    const Accumulation acc = renderer.render({0, 0, 24, 24}, 0, 8, nullptr);
    EXPECT_TRUE(test::all_finite(acc)) << "case " << i << ": " << acc.nan_dropped << " NaN, "
                                       << acc.inf_dropped << " Inf";
    EXPECT_GT(test::mean_luminance(acc).mean, 0.0) << "case " << i;
  }
}

TEST(PrincipledRender, WhiteMetalAndGlassInAFurnaceStayBelowTheEnvironment) {
  // Single-scattering microfacet lobes lose energy and never gain it: the whole image (sphere
  // and background alike) is at most the environment's radiance, and the smooth ones nearly it.
  PrincipledParameters metal, glass;
  metal.metallic = {1, -1};
  metal.roughness = {0.3, -1};
  glass.spec_trans = {1, -1};
  glass.roughness = {0.3, -1};
  for (const PrincipledParameters& p : {metal, glass}) {
    const double le = 0.7;
    const Renderer renderer(principled_sphere(p, {1, 1, 1}, le), test::test_job(16, 16, 64));
    const Accumulation acc = renderer.render({0, 0, 16, 16}, 0, 64, nullptr);
    ASSERT_TRUE(test::all_finite(acc));
    const test::Estimate e = test::mean_luminance(acc);
    EXPECT_GT(e.se, 0.0);
    EXPECT_LE(e.mean, le + test::kSigmas * e.se + test::kFloatRounding);
    EXPECT_GT(e.mean, 0.8 * le);
  }
}

TEST(PrincipledThinRender, AWhiteDiffuseTransmitterShowsTheEnvironment) {
  // diff_trans 2, spec_trans 0, base_color 1: every hit sends all light on through the sheet,
  // from whichever side it arrives (inside the sphere too), so the image is the environment's
  // radiance. Then every lobe together renders finite.
  Scene s = principled_sphere({}, {1, 1, 1}, 0.7);
  s.materials[0].type = MaterialType::principled_thin;
  s.materials[0].principled.diff_trans = {2, -1};
  const Renderer white(s, test::test_job(16, 16, 64));
  const Accumulation acc = white.render({0, 0, 16, 16}, 0, 64, nullptr);
  ASSERT_TRUE(test::all_finite(acc));
  const test::Estimate e = test::mean_luminance(acc);
  EXPECT_NEAR(e.mean, 0.7, test::kSigmas * e.se + test::kFloatRounding);

  PrincipledParameters& p = s.materials[0].principled;
  p.diff_trans = {1.4, -1};
  p.spec_trans = {0.5, -1};
  p.anisotropic = {0.5, -1};
  p.sheen = p.sheen_tint = p.flatness = p.spec_tint = {0.5, -1};
  s.materials[0].reflectance.value = {0.8, 0.5, 0.2};
  s.materials[0].ior = 1.33;
  const Renderer every(s, test::test_job(24, 24, 8));
  const Accumulation all = every.render({0, 0, 24, 24}, 0, 8, nullptr);
  EXPECT_TRUE(test::all_finite(all)) << all.nan_dropped << " NaN, " << all.inf_dropped << " Inf";
  EXPECT_GT(test::mean_luminance(all).mean, 0.0);
}

TEST(PPlasticRender, RendersFiniteAndBelowTheEnvironment) {
  // Its coating reflects F and passes 1 - F twice to a white base: at most the environment.
  Scene s = principled_sphere({}, {1, 1, 1}, 0.7);
  s.materials[0].type = MaterialType::pplastic;
  s.materials[0].distribution = MicrofacetDistribution::ggx;
  s.materials[0].alpha_u = {0.1, -1};
  s.materials[0].alpha_v = {0.4, -1};
  const Renderer renderer(s, test::test_job(16, 16, 64));
  const Accumulation acc = renderer.render({0, 0, 16, 16}, 0, 64, nullptr);
  ASSERT_TRUE(test::all_finite(acc));
  const test::Estimate e = test::mean_luminance(acc);
  EXPECT_LE(e.mean, 0.7 + test::kSigmas * e.se + test::kFloatRounding);
  EXPECT_GT(e.mean, 0.5);
}

TEST(BlendRender, NestedKindsRenderFinite) {
  // A blend of a rough plastic (its table made for the nested material) and a rough glass (the
  // blend then transmits), and a blend nesting that blend and a principled metal.
  Material plastic;
  plastic.type = MaterialType::rough_plastic;
  plastic.alpha_u = plastic.alpha_v = {0.3, -1};
  plastic.reflectance.value = {0.8, 0.2, 0.2};
  Material glass;
  glass.type = MaterialType::rough_glass;
  glass.alpha_u = glass.alpha_v = {0.2, -1};
  Material metal;
  metal.type = MaterialType::principled;
  metal.principled.metallic = {1, -1};
  Material inner;
  inner.type = MaterialType::blend;
  inner.blend_weight = {0.4, -1};
  inner.blend = {plastic, glass};
  Material outer;
  outer.type = MaterialType::blend;
  outer.blend_weight = {0.7, -1};
  outer.blend = {inner, metal};
  for (const Material& m : {inner, outer}) {
    Scene s = principled_sphere({}, {0.5, 0.5, 0.5}, 1.0);
    s.materials[0] = m;
    s.materials[0].name = "blend";
    const Renderer renderer(s, test::test_job(24, 24, 8));
    const Accumulation acc = renderer.render({0, 0, 24, 24}, 0, 8, nullptr);
    EXPECT_TRUE(test::all_finite(acc)) << acc.nan_dropped << " NaN, " << acc.inf_dropped << " Inf";
    EXPECT_GT(test::mean_luminance(acc).mean, 0.0);
  }
}

}  // namespace
}  // namespace tessera
