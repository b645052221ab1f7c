#include "shading_normal.h"

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace tessera {
namespace {

void expect_near(glm::vec3 a, glm::vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(ShadingNormal, TangentIsDpduMadeOrthogonalToTheNormal) {
  expect_near(shading_tangent({2, 0, 0.5f}, {0, 0, 1}), {1, 0, 0});
  const glm::vec3 n = glm::normalize(glm::vec3(1, 2, 3));
  const glm::vec3 s = shading_tangent({0.3f, -1, 2}, n);
  EXPECT_NEAR(glm::dot(s, n), 0, 1e-6f);
  EXPECT_NEAR(glm::length(s), 1, 1e-6f);
  // No parametrisation, or dpdu along the normal: the basis around the normal.
  for (const glm::vec3 dpdu : {glm::vec3(0), 2.0f * n}) {
    const glm::vec3 fallback = shading_tangent(dpdu, n);
    EXPECT_NEAR(glm::dot(fallback, n), 0, 1e-6f);
    EXPECT_NEAR(glm::length(fallback), 1, 1e-6f);
  }
}

TEST(ShadingNormal, NormalMapTexelsMapToTheShadingFrame) {
  const glm::vec3 dpdu(2, 0, 0.5f), dpdv(0, 3, 0), ns(0, 0, 1);
  expect_near(normal_mapped({0.5f, 0.5f, 1.0f}, dpdu, dpdv, ns), ns);         // flat
  expect_near(normal_mapped({1.0f, 0.5f, 0.5f}, dpdu, dpdv, ns), {1, 0, 0});  // along +u
  expect_near(normal_mapped({0.5f, 1.0f, 0.5f}, dpdu, dpdv, ns), {0, 1, 0});  // ns x s
  expect_near(normal_mapped({1.0f, 0.5f, 1.0f}, dpdu, dpdv, ns),
              glm::normalize(glm::vec3(1, 0, 1)));
  // Mid-grey maps to no direction: the shading normal stays.
  expect_near(normal_mapped({0.5f, 0.5f, 0.5f}, dpdu, dpdv, ns), ns);
}

TEST(ShadingNormal, NormalMapIsEquivariantUnderRotation) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1), t(0, 1);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 ns = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
    const glm::vec3 dpdu(u(rng), u(rng), u(rng)), dpdv(u(rng), u(rng), u(rng));
    const glm::vec3 texel(t(rng), t(rng), 0.5f + 0.5f * t(rng));
    const glm::mat3 r(
        glm::rotate(glm::mat4(1), 2.0f * u(rng), glm::normalize(glm::vec3(u(rng), u(rng), 1))));
    const glm::vec3 n = normal_mapped(texel, dpdu, dpdv, ns);
    expect_near(normal_mapped(texel, r * dpdu, r * dpdv, r * ns), r * n, 1e-4f);
    EXPECT_NEAR(glm::length(n), 1, 1e-5f);
    // The texel's blue channel is the cosine to ns of the unnormalised direction.
    const glm::vec3 local = glm::normalize(texel * 2.0f - 1.0f);
    EXPECT_NEAR(glm::dot(n, ns), local.z, 1e-4f);
  }
}

TEST(ShadingNormal, BumpMapIsTheNormalOfTheDisplacedSurface) {
  // The plane z = 0 with p(u, v) = (u, v, 0) displaced to (u, v, scale h(u, v)): its normal is
  // (-scale dh/du, -scale dh/dv, 1), normalised.
  const glm::vec3 dpdu(1, 0, 0), dpdv(0, 1, 0), ns(0, 0, 1);
  expect_near(bump_mapped({0, 0}, 1, dpdu, dpdv, ns, ns), ns);
  expect_near(bump_mapped({0.5f, -2}, 0.3f, dpdu, dpdv, ns, ns),
              glm::normalize(glm::vec3(-0.15f, 0.6f, 1)));
  // A parametrisation stretched along u: the same height slope per unit length tilts alike.
  expect_near(bump_mapped({1.0f, 0}, 1, {2, 0, 0}, dpdv, ns, ns),
              glm::normalize(glm::vec3(-0.5f, 0, 1)));
  // Turned to the side of the geometric normal.
  expect_near(bump_mapped({0.5f, -2}, 0.3f, dpdu, dpdv, ns, {0, 0, -1}),
              -glm::normalize(glm::vec3(-0.15f, 0.6f, 1)));
  // No parametrisation: the shading normal stays.
  expect_near(bump_mapped({0.5f, 1}, 1, glm::vec3(0), glm::vec3(0), ns, ns), ns);
}

TEST(ShadingNormal, BumpMapMatchesFiniteDifferencesOnACurvedPatch) {
  // p(u, v) on a cylinder of radius 2, displaced by h(u, v) = 0.1 sin(3u) cos(2v) along the
  // shading normal at the point of interest. Mitsuba's bump map ignores the normal's own change
  // (dn/du), so the displacement direction is held fixed: the displaced surface's tangents by
  // central differences then give the normal the bump map must return.
  const auto p = [](float u, float v) { return glm::vec3(2 * std::cos(u), 2 * std::sin(u), v); };
  const auto n_at = [](float u) { return glm::vec3(std::cos(u), std::sin(u), 0); };
  const auto h = [](float u, float v) { return 0.1f * std::sin(3 * u) * std::cos(2 * v); };
  for (float u = 0.1f; u < 3; u += 0.37f) {
    for (float v = -1; v < 1; v += 0.29f) {
      const float scale = 1.5f;
      const glm::vec3 dpdu(-2 * std::sin(u), 2 * std::cos(u), 0), dpdv(0, 0, 1);
      const glm::vec2 grad(0.3f * std::cos(3 * u) * std::cos(2 * v),
                           -0.2f * std::sin(3 * u) * std::sin(2 * v));
      const glm::vec3 n = bump_mapped(grad, scale, dpdu, dpdv, n_at(u), n_at(u));
      const float e = 1e-2f;
      const auto q = [&](float uu, float vv) { return p(uu, vv) + scale * h(uu, vv) * n_at(u); };
      const glm::vec3 tu = q(u + e, v) - q(u - e, v), tv = q(u, v + e) - q(u, v - e);
      expect_near(n, glm::normalize(glm::cross(tu, tv)), 2e-4f);
    }
  }
}

struct MitsubaShading {
  int kind;       ///< 0 normal map, 1 bump map
  float a, b, c;  ///< texel rgb, or the height's (d/du, d/dv) and the bump scale
  float dpdu[3], dpdv[3], ns[3], ng[3], wi[3], wo[3];
  float value;  ///< Mitsuba's diffuse value * pi / reflectance
};

/// Mitsuba 3's normalmap and bumpmap adapters (defaults: flip_invalid_normals and
/// use_shadowing_function on) over a diffuse BSDF, on a triangle with tilted vertex normals and
/// skewed texture coordinates, hit from several directions
/// (worker/render/texture/mitsuba_shading_reference.py).
const MitsubaShading kMitsuba[] = {
#include "mitsuba_shading_reference.inc"
};

glm::vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }

/// The diffuse value * pi / reflectance the adapters' contract gives (shading_normal.h).
float adapted_diffuse(glm::vec3 n, glm::vec3 ns, glm::vec3 wi, glm::vec3 wo) {
  const bool same_side = glm::dot(wo, ns) * glm::dot(wo, n) > 0;
  if (!same_side || glm::dot(wi, n) <= 0 || glm::dot(wo, n) <= 0) return 0;
  return glm::dot(wo, n) * shadow_terminator(n, ns, wo);
}

TEST(ShadingNormal, MatchesMitsubasAdapters) {
  int normal_maps = 0, bump_maps = 0, flipped = 0, shadowed = 0, zero = 0;
  for (const MitsubaShading& m : kMitsuba) {
    const glm::vec3 ns = v3(m.ns), wi = v3(m.wi), wo = v3(m.wo);
    const glm::vec3 n =
        m.kind == 0 ? normal_mapped({m.a, m.b, m.c}, v3(m.dpdu), v3(m.dpdv), ns, wi)
                    : bump_mapped({m.a, m.b}, m.c, v3(m.dpdu), v3(m.dpdv), ns, v3(m.ng), wi);
    const glm::vec3 unflipped =
        m.kind == 0 ? normal_mapped({m.a, m.b, m.c}, v3(m.dpdu), v3(m.dpdv), ns)
                    : bump_mapped({m.a, m.b}, m.c, v3(m.dpdu), v3(m.dpdv), ns, v3(m.ng));
    EXPECT_NEAR(adapted_diffuse(n, ns, wi, wo), m.value, 2e-6f)
        << "kind " << m.kind << " " << m.a << " " << m.b << " " << m.c << " wi " << wi.x << ","
        << wi.y << "," << wi.z;
    (m.kind == 0 ? normal_maps : bump_maps) += 1;
    flipped += glm::dot(n, unflipped) < 0.9999f;
    shadowed += shadow_terminator(n, ns, wo) < 0.999f;
    zero += m.value == 0;
  }
  EXPECT_EQ(normal_maps, 4 * 48);
  EXPECT_EQ(bump_maps, 3 * 48);
  // The table exercises the flip, the shadowing and the rejected directions.
  EXPECT_GT(flipped, 10);
  EXPECT_GT(shadowed, 100);
  EXPECT_GT(zero, 10);
}

TEST(ShadingNormal, ShadowTerminator) {
  const glm::vec3 ns(0, 0, 1), tilted = glm::normalize(glm::vec3(0.5f, 0, 1));
  EXPECT_EQ(shadow_terminator(ns, ns, glm::normalize(glm::vec3(1, 0, 0.01f))), 1.0f);
  EXPECT_EQ(shadow_terminator(tilted, ns, ns), 1.0f);
  // tan^2 of the tilt is 1/4: a2 = 1/32; wo at 60 degrees: tan^2 = 3.
  const glm::vec3 wo(std::sqrt(3.0f) / 2, 0, 0.5f);
  EXPECT_NEAR(shadow_terminator(tilted, ns, wo), 2 / (1 + std::sqrt(1 + 3.0f / 32)), 1e-6f);
  EXPECT_EQ(shadow_terminator(tilted, ns, {1, 0, 0}), 0.0f);  // grazing: fully shadowed
  expect_near(perturbed_tangent(tilted, {1, 0, 0}), glm::normalize(glm::vec3(1, 0, -0.5f)));
}

}  // namespace
}  // namespace tessera
