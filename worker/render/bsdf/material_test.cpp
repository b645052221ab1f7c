// The render form of materials: every parameter that principled_thin and pplastic let a texture
// give reaches BsdfParams looked up at the hit's uv, and the flags the integrator reads
// (dielectric(), textured) say what these types are.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/material.h"
#include "render/bsdf/rough_plastic_tables.h"
#include "render/texture/texture_set.h"

namespace tessera::test {
namespace {

/// A checkerboard of scalar values 1.4 and 0.4 (diff_trans and eta go beyond 1).
TextureSet checker() {
  Texture c;
  c.kind = TextureKind::checkerboard;
  c.color0 = glm::dvec3(1.4);
  c.color1 = glm::dvec3(0.4);
  return TextureSet({c}, [](const std::string& path) -> std::string {
    throw std::runtime_error("no file expected: " + path);
  });
}

TEST(RenderMaterial, PrincipledThinLooksUpEveryTexturedParameter) {
  Material m;
  m.type = MaterialType::principled_thin;
  m.reflectance = {{0.5, 0.25, 1.0}, 0};
  m.ior = 1.25;
  m.ior_texture = 0;
  PrincipledParameters& p = m.principled;
  p.roughness = {0.5, 0};
  p.anisotropic = {0.25, 0};
  p.spec_trans = {0.5, 0};
  p.spec_tint = {0.5, 0};
  p.sheen = {0.5, 0};
  p.sheen_tint = {0.5, 0};
  p.flatness = {0.5, 0};
  p.diff_trans = {1.0, 0};
  p.specular_transmittance_sampling_rate = 3;
  RoughPlasticTables tables;
  const RenderMaterial r = make_render_material(m, tables);
  EXPECT_TRUE(r.textured);
  EXPECT_TRUE(r.dielectric());  // both sides are the sheet
  const TextureSet set = checker();
  for (glm::vec2 uv : {glm::vec2(0.1f, 0.1f), glm::vec2(0.6f, 0.1f)}) {
    const float t = set.lookup_1(0, uv);
    const BsdfParams b = bsdf_params(r, set, TexturePoint{uv});
    EXPECT_EQ(b.type, MaterialType::principled_thin);
    EXPECT_EQ(b.reflectance, glm::vec3(0.5f, 0.25f, 1.0f) * set.lookup(0, uv));
    EXPECT_FLOAT_EQ(b.eta, 1.25f * t);
    EXPECT_FLOAT_EQ(b.principled.roughness, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.anisotropic, 0.25f * t);
    EXPECT_FLOAT_EQ(b.principled.spec_trans, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.spec_tint, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.sheen, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.sheen_tint, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.flatness, 0.5f * t);
    EXPECT_FLOAT_EQ(b.principled.diff_trans, t);  // 1.4 stays 1.4: its range is [0, 2]
    EXPECT_EQ(b.principled.specular_transmittance_sampling_rate, 3.0f);
  }
}

TEST(RenderMaterial, PplasticLooksUpItsTexturedIndexAndAlphas) {
  Material m;
  m.type = MaterialType::pplastic;
  m.ior = 1.5;
  m.ior_texture = 0;
  m.alpha_u = {0.1, -1};
  m.alpha_v = {0.5, 0};
  RoughPlasticTables tables;
  const RenderMaterial r = make_render_material(m, tables);
  EXPECT_TRUE(r.textured);
  EXPECT_FALSE(r.dielectric());  // one-sided, as Mitsuba's
  EXPECT_EQ(tables.size(), 0u);
  const TextureSet set = checker();
  const glm::vec2 uv(0.6f, 0.1f);
  const BsdfParams b = bsdf_params(r, set, TexturePoint{uv});
  EXPECT_FLOAT_EQ(b.eta, 1.5f * set.lookup_1(0, uv));
  EXPECT_FLOAT_EQ(b.alpha_u, 0.1f);
  EXPECT_FLOAT_EQ(b.alpha_v, 0.5f * set.lookup_1(0, uv));
}

}  // namespace
}  // namespace tessera::test
