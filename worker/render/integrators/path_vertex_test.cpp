// path_vertex's shortcuts against the general code they stand in for, bit for bit.
#include "render/integrators/path_vertex.h"

#include <cstring>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"
#include "render/bsdf/material.h"
#include "render/bsdf/rough_plastic_tables.h"
#include "render/sampling/warp.h"
#include "render/texture/texture_set.h"

namespace tessera::test {
namespace {

uint32_t float_bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(BsdfSampling, SmoothSpecularShortcutIsTheBsdfsBits) {
  // path_vertex samples untextured smooth glass, mirrors and smooth conductors without building
  // the general Bsdf (path_vertex_detail::specular_sample): the same sample, bit for bit, as
  // Bsdf(bsdf_params(...)).sample, from either side, at normal and grazing incidence.
  Material glass;
  glass.type = MaterialType::glass;
  glass.ior = 1.5;
  glass.specular_reflectance = {{0.9, 0.8, 0.7}, -1};
  glass.specular_transmittance = {{0.6, 0.75, 1.0}, -1};
  Material inverted = glass;
  inverted.ior = 0.7;
  Material mirror;
  mirror.type = MaterialType::mirror;
  mirror.specular_reflectance = {{0.8, 0.9, 1.0}, -1};
  Material gold;
  gold.type = MaterialType::conductor;
  gold.specular_reflectance = {{1.0, 0.95, 0.9}, -1};
  gold.eta = {0.143, 0.374, 1.442};
  gold.k = {3.983, 2.385, 1.603};
  Material perfect = gold;
  perfect.perfect = true;
  RoughPlasticTables tables;
  const TextureSet textures({}, [](const std::string& path) -> std::string {
    throw std::runtime_error("no file expected: " + path);
  });
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const glm::vec3 fixed[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.6f, 0, -0.8f}, {0.999f, 0, 0.0447f}};
  int samples = 0;
  for (const Material& m : {glass, inverted, mirror, gold, perfect}) {
    const RenderMaterial r = make_render_material(m, tables);
    ASSERT_TRUE(path_vertex_detail::smooth_specular(r)) << int(m.type);
    const Bsdf bsdf(bsdf_params(r, textures, TexturePoint{}));
    for (int i = 0; i < 4000; ++i) {
      const glm::vec3 wo = i < 5 ? glm::normalize(fixed[i]) : square_to_uniform_sphere({u01(rng), u01(rng)});
      const float u_lobe = u01(rng);
      const std::optional<BsdfSample> a = path_vertex_detail::specular_sample(r, wo, u_lobe);
      const std::optional<BsdfSample> b = bsdf.sample(wo, u_lobe, glm::vec2(u01(rng), u01(rng)));
      ASSERT_EQ(a.has_value(), b.has_value()) << int(m.type) << " sample " << i;
      if (!a) continue;
      ++samples;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(float_bits(a->wi[c]), float_bits(b->wi[c])) << int(m.type) << " sample " << i;
        EXPECT_EQ(float_bits(a->weight[c]), float_bits(b->weight[c])) << int(m.type) << " sample " << i;
      }
      EXPECT_EQ(float_bits(a->pdf), float_bits(b->pdf)) << int(m.type) << " sample " << i;
      EXPECT_EQ(float_bits(a->eta), float_bits(b->eta)) << int(m.type) << " sample " << i;
      EXPECT_EQ(a->delta, b->delta);
    }
  }
  EXPECT_GT(samples, 12000);  // the mirror and conductors end half of theirs (wo below the surface)
  // A textured parameter, or any other kind, takes the general path.
  Material textured = glass;
  textured.specular_transmittance.texture = 0;
  EXPECT_FALSE(path_vertex_detail::smooth_specular(make_render_material(textured, tables)));
  Material thin = glass;
  thin.type = MaterialType::thin_glass;
  EXPECT_FALSE(path_vertex_detail::smooth_specular(make_render_material(thin, tables)));
}

}  // namespace
}  // namespace tessera::test
