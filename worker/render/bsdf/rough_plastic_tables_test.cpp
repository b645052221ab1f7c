// The scene's rough plastic tables: one per distinct coating, shared by every material (and
// nested material) with that coating, and equal to a table made directly.
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "render/bsdf/material.h"
#include "render/bsdf/rough_plastic_tables.h"
#include "scene/scene_error.h"

namespace tessera::test {
namespace {

Material rough_plastic(double alpha, double ior, glm::dvec3 colour) {
  Material m;
  m.type = MaterialType::rough_plastic;
  m.alpha_u = m.alpha_v = {alpha, -1};
  m.ior = ior;
  m.reflectance.value = colour;
  return m;
}

TEST(RoughPlasticTables, OneTablePerCoatingSharedByItsMaterials) {
  RoughPlasticTables tables;
  Material red = rough_plastic(0.3, 1.5, {0.8, 0.1, 0.1});
  Material green = rough_plastic(0.3, 1.5, {0.1, 0.8, 0.1});
  green.nonlinear = true;  // neither colour nor nonlinear changes the table
  green.sample_visible = false;
  Material other = rough_plastic(0.3, 1.33, {0.5, 0.5, 0.5});
  Material blend;
  blend.type = MaterialType::blend;
  blend.blend = {rough_plastic(0.3, 1.5, {0, 0, 0}), Material{}};
  const RenderMaterial a = make_render_material(red, tables);
  const RenderMaterial b = make_render_material(green, tables);
  const RenderMaterial c = make_render_material(other, tables);
  const RenderMaterial d = make_render_material(blend, tables);
  EXPECT_EQ(tables.size(), 2u);
  ASSERT_NE(a.rough_plastic, nullptr);
  EXPECT_EQ(a.rough_plastic, b.rough_plastic);
  EXPECT_EQ(a.rough_plastic, d.blend[0].rough_plastic);
  EXPECT_NE(a.rough_plastic, c.rough_plastic);
  EXPECT_EQ(c.rough_plastic->eta, 1.33f);

  const RoughPlasticTable direct = make_rough_plastic_table(MicrofacetDistribution::beckmann,
                                                            0.3f, 1.5f);
  EXPECT_EQ(a.rough_plastic->internal_reflectance, direct.internal_reflectance);
  EXPECT_EQ(a.rough_plastic->external_transmittance, direct.external_transmittance);
  EXPECT_EQ(tables.get(MicrofacetDistribution::beckmann, 0.3f, 1.5f), a.rough_plastic);
  EXPECT_EQ(tables.size(), 2u);
}

// make_rough_plastic_table integrates its angles on the caller's TBB threads: the table must
// not depend on how many.
TEST(RoughPlasticTables, OneThreadAndAllThreadsMakeTheSameTable) {
  struct Coating {
    MicrofacetDistribution distribution;
    float alpha, eta;
  };
  for (const Coating& c : {Coating{MicrofacetDistribution::beckmann, 0.1f, 1.5f},
                           Coating{MicrofacetDistribution::ggx, 0.4f, 2.0f},
                           Coating{MicrofacetDistribution::ggx, 0.005f, 1.33f}}) {
    // (Named, not structured bindings: clang 14, the sanitizer pass's compiler, cannot capture
    // those in the lambda.)
    const MicrofacetDistribution distribution = c.distribution;
    const float alpha = c.alpha, eta = c.eta;
    RoughPlasticTable one;
    tbb::task_arena(1).execute([&] { one = make_rough_plastic_table(distribution, alpha, eta); });
    const RoughPlasticTable all = make_rough_plastic_table(distribution, alpha, eta);
    EXPECT_EQ(std::memcmp(one.external_transmittance.data(), all.external_transmittance.data(),
                          sizeof(float) * RoughPlasticTable::kResolution),
              0)
        << "alpha " << alpha << ", eta " << eta;
    EXPECT_EQ(std::memcmp(&one.internal_reflectance, &all.internal_reflectance, sizeof(float)), 0)
        << "alpha " << alpha << ", eta " << eta;
    EXPECT_GT(all.internal_reflectance, 0.0f);
  }
}

TEST(RoughPlasticTables, RefusesParametersThatMakeNoTable) {
  RoughPlasticTables tables;
  EXPECT_THROW(tables.get(MicrofacetDistribution::ggx, 0.0f, 1.5f), std::invalid_argument);
  EXPECT_THROW(tables.get(MicrofacetDistribution::ggx, 0.1f, std::nanf("")),
               std::invalid_argument);
  Material textured = rough_plastic(0.3, 1.5, {0.5, 0.5, 0.5});
  textured.alpha_u.texture = 0;
  EXPECT_THROW(make_render_material(textured, tables), SceneError);
  EXPECT_EQ(tables.size(), 0u);
}

}  // namespace
}  // namespace tessera::test
