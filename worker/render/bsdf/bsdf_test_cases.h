// Test support: the grid of BSDF parameters and outgoing directions the BSDF tests run over.
#pragma once

#include <cmath>
#include <deque>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "render/bsdf/bsdf.h"
#include "render/bsdf/chi_square.h"

namespace tessera::test {

inline bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// mitsuba_blend.py's CASES, in its order: a rough conductor and a diffuse BSDF (0.3), a rough
/// dielectric and a diffuse BSDF (0.6, eta on the blend for the reciprocity test), and a blend
/// of the second with a principled metal (0.25).
inline std::vector<BsdfParams> mitsuba_blend_cases() {
  BsdfParams diffuse;
  diffuse.reflectance = {0.7f, 0.5f, 0.3f};
  BsdfParams metal;
  metal.type = MaterialType::rough_conductor;
  metal.distribution = MicrofacetDistribution::ggx;
  metal.alpha_u = metal.alpha_v = 0.2f;
  metal.conductor_eta = {0.2f, 0.9f, 1.1f};
  metal.conductor_k = {3.9f, 2.4f, 2.2f};
  BsdfParams glass;
  glass.type = MaterialType::rough_glass;
  glass.distribution = MicrofacetDistribution::beckmann;
  glass.alpha_u = glass.alpha_v = 0.3f;
  glass.eta = 1.5f;
  BsdfParams principled_metal;
  principled_metal.type = MaterialType::principled;
  principled_metal.reflectance = {0.9f, 0.6f, 0.3f};
  principled_metal.eta = 1.5f;
  principled_metal.principled.metallic = 1.0f;
  principled_metal.principled.roughness = 0.4f;
  auto blend = [](float weight, const BsdfParams& a, const BsdfParams& b) {
    BsdfParams p;
    p.type = MaterialType::blend;
    p.blend_weight = weight;
    p.blend = {a, b};
    return p;
  };
  BsdfParams glass_and_diffuse = blend(0.6f, glass, diffuse);
  glass_and_diffuse.eta = 1.5f;  // the reciprocity test reads the interface's index here
  return {blend(0.3f, metal, diffuse), glass_and_diffuse,
          blend(0.25f, glass_and_diffuse, principled_metal)};
}

struct BsdfCase {
  std::string name;
  BsdfParams params;
  bool two_sided_wo = false;  ///< dielectrics: also test wo below the surface
};

/// Every BSDF kind over a grid of parameters; owns the rough plastic tables it points to.
class BsdfCases {
 public:
  /// rough_plastic = false leaves out the rough plastic cases (their tables take ~0.25 s each).
  explicit BsdfCases(bool rough_plastic = true) {
    const glm::vec3 gold_eta(0.2f, 0.9f, 1.1f), gold_k(3.9f, 2.4f, 2.2f);
    BsdfParams p;
    p.reflectance = {0.7f, 0.5f, 0.3f};
    add("diffuse", p);

    p = BsdfParams{};
    p.type = MaterialType::conductor;
    p.conductor_eta = gold_eta;
    p.conductor_k = gold_k;
    add("conductor gold", p);
    p.perfect = true;
    add("conductor perfect", p);
    p = BsdfParams{};
    p.type = MaterialType::mirror;
    add("mirror", p);
    for (float eta : {1.5f, 1.0f / 1.5f}) {
      p = BsdfParams{};
      p.type = MaterialType::glass;
      p.eta = eta;
      add("glass eta " + std::to_string(eta), p, true);
      p.type = MaterialType::thin_glass;
      add("thin glass eta " + std::to_string(eta), p, true);
    }

    const struct {
      float u, v;
    } alphas[] = {{0.15f, 0.15f}, {0.6f, 0.6f}, {0.1f, 0.5f}};
    for (auto dist : {MicrofacetDistribution::beckmann, MicrofacetDistribution::ggx}) {
      const std::string d = dist == MicrofacetDistribution::ggx ? "ggx" : "beckmann";
      for (auto a : alphas) {
        for (bool visible : {true, false}) {
          const std::string tag = d + " alpha " + std::to_string(a.u) + "/" + std::to_string(a.v) +
                                  (visible ? " visible" : " all normals");
          p = BsdfParams{};
          p.distribution = dist;
          p.alpha_u = a.u;
          p.alpha_v = a.v;
          p.sample_visible = visible;
          p.type = MaterialType::rough_conductor;
          p.conductor_eta = gold_eta;
          p.conductor_k = gold_k;
          add("rough conductor " + tag, p);
          p.type = MaterialType::rough_glass;
          p.eta = 1.5f;
          add("rough glass " + tag, p, true);
        }
      }
      p = BsdfParams{};
      p.type = MaterialType::rough_glass;
      p.distribution = dist;
      p.alpha_u = p.alpha_v = 0.3f;
      p.eta = 0.75f;
      add("rough glass " + d + " eta 0.75", p, true);

      for (float alpha : {0.15f, 0.6f}) {
        if (!rough_plastic) break;
        for (bool nonlinear : {false, true}) {
          p = BsdfParams{};
          p.type = MaterialType::rough_plastic;
          p.distribution = dist;
          p.alpha_u = p.alpha_v = alpha;
          p.reflectance = {0.8f, 0.5f, 0.2f};
          p.nonlinear = nonlinear;
          p.sample_visible = !nonlinear;  // both samplers, without doubling the grid
          add("rough plastic " + d + " alpha " + std::to_string(alpha) +
                  (nonlinear ? " nonlinear all normals" : " visible"),
              with_table(p));
        }
      }
    }
    for (bool nonlinear : {false, true}) {
      p = BsdfParams{};
      p.type = MaterialType::plastic;
      p.reflectance = {0.8f, 0.5f, 0.2f};
      p.nonlinear = nonlinear;
      add(std::string("plastic") + (nonlinear ? " nonlinear" : ""), p);
    }
    add_principled();
    add_principled_thin();
    add_pplastic();
    add_blends();
  }

  const std::vector<BsdfCase>& all() const { return cases_; }

  /// The cases of one material type.
  std::vector<BsdfCase> of(MaterialType type) const {
    std::vector<BsdfCase> out;
    for (const BsdfCase& c : cases_) {
      if (c.params.type == type) out.push_back(c);
    }
    return out;
  }

  /// Points p at a rough plastic table owned by this object.
  BsdfParams with_table(BsdfParams p) {
    p.rough_plastic = nullptr;
    for (const RoughPlasticTable& t : tables_) {
      const bool same = t.distribution == p.distribution && t.alpha == p.alpha_u && t.eta == p.eta;
      if (same) p.rough_plastic = &t;
    }
    if (!p.rough_plastic) {
      tables_.push_back(make_rough_plastic_table(p.distribution, p.alpha_u, p.eta));
      p.rough_plastic = &tables_.back();
    }
    return p;
  }

 private:
  /// Mitsuba's blendbsdf: mitsuba_blend_cases() 0 and 1 (smooth lobes of different kinds, a
  /// transmitting one) and a nested blend whose second BSDF is a rough conductor (the third of
  /// mitsuba_blend_cases() holds a principled metal, whose pdf() from below is Mitsuba's but
  /// which samples nothing there, so that a chi-square test of it from below cannot pass).
  void add_blends() {
    const std::vector<BsdfParams> mitsuba = mitsuba_blend_cases();
    add("blend rough conductor and diffuse 0.3", mitsuba[0]);
    add("blend rough glass and diffuse 0.6", mitsuba[1], true);
    BsdfParams p = mitsuba[2];
    p.blend[1] = mitsuba[0].blend[0];
    add("blend of a blend and a rough conductor", p, true);
  }

  /// Mitsuba's principled: each lobe alone and together, transmission from both sides.
  void add_principled() {
    BsdfParams p;
    p.type = MaterialType::principled;
    p.reflectance = {0.8f, 0.5f, 0.2f};
    p.eta = 1.5f;
    add("principled defaults", p);
    PrincipledInputs& in = p.principled;
    in.roughness = 0.3f;
    in.anisotropic = 0.6f;
    in.metallic = 0.7f;
    in.spec_tint = 0.4f;
    add("principled metallic anisotropic", p);
    in = PrincipledInputs{};
    in.roughness = 0.7f;
    in.sheen = 0.8f;
    in.sheen_tint = 0.5f;
    in.flatness = 0.6f;
    in.clearcoat = 0.7f;
    in.clearcoat_gloss = 0.4f;
    add("principled sheen flatness clearcoat", p);
    in = PrincipledInputs{};
    // Lobes sharper than alpha ~ 0.05 are too narrow for the chi-square test's integration
    // grid at grazing angles; principled_test.cpp evaluates sharper ones against Mitsuba.
    in.roughness = 0.45f;
    in.spec_trans = 0.8f;
    in.transmits = true;
    add("principled transmission eta 1.5", p, true);
    in.roughness = 0.35f;
    in.spec_trans = 1.0f;
    p.eta = 0.75f;
    add("principled transmission eta 0.75", p, true);
    p.eta = 1.33f;
    in = PrincipledInputs{0.4f, 0.4f, 0.3f, 0.5f, 0.6f, 0.4f, 0.0f, 0.3f, 1.0f, 0.5f,
                          0.5f, 2.0f, 1.5f, true};
    add("principled every lobe, sampling rates", p, true);
  }

  /// Mitsuba's principledthin: each lobe alone and together, from both sides of the sheet.
  void add_principled_thin() {
    BsdfParams p;
    p.type = MaterialType::principled_thin;
    p.reflectance = {0.8f, 0.5f, 0.2f};
    p.eta = 1.5f;
    add("principled thin defaults", p, true);
    PrincipledInputs& in = p.principled;
    // The transmission's alpha is ((0.65 eta - 0.35) roughness)^2: rough enough here for the
    // chi-square test's integration grid (principled_thin_test.cpp evaluates sharper ones
    // against Mitsuba).
    in.roughness = 0.7f;
    in.anisotropic = 0.5f;
    in.spec_trans = 0.8f;
    in.spec_tint = 0.4f;
    p.eta = 1.33f;
    add("principled thin specular anisotropic", p, true);
    in = PrincipledInputs{};
    in.roughness = 0.7f;
    in.spec_trans = 0.3f;
    in.sheen = 0.6f;
    in.sheen_tint = 0.5f;
    in.flatness = 0.5f;
    in.diff_trans = 1.4f;
    in.diffuse_reflectance_sampling_rate = 0.5f;
    in.specular_reflectance_sampling_rate = 2.0f;
    in.specular_transmittance_sampling_rate = 1.5f;
    in.diffuse_transmittance_sampling_rate = 0.7f;
    add("principled thin every lobe, sampling rates", p, true);
    in = PrincipledInputs{};
    in.roughness = 0.6f;
    in.spec_trans = 1.0f;
    p.eta = 1.5f;
    add("principled thin specular only", p, true);
  }

  /// Mitsuba's pplastic (RGB variants): isotropic and anisotropic, both samplers.
  void add_pplastic() {
    BsdfParams p;
    p.type = MaterialType::pplastic;
    p.reflectance = {0.8f, 0.5f, 0.2f};
    p.distribution = MicrofacetDistribution::ggx;
    p.alpha_u = p.alpha_v = 0.2f;
    add("pplastic ggx 0.2", p);
    p.distribution = MicrofacetDistribution::beckmann;
    p.alpha_u = 0.1f;
    p.alpha_v = 0.4f;
    p.sample_visible = false;
    p.eta = 1.33f;
    add("pplastic beckmann 0.1/0.4 all normals", p);
  }

  void add(std::string name, const BsdfParams& p, bool two_sided = false) {
    cases_.push_back({std::move(name), p, two_sided});
  }

  std::deque<RoughPlasticTable> tables_;  // stable addresses
  std::vector<BsdfCase> cases_;
};

/// Outgoing directions: normal, moderate, steep and grazing incidence (phi = 0.5 rad so that
/// anisotropy matters), mirrored below the surface when `below`.
inline std::vector<glm::vec3> test_wos(bool below) {
  std::vector<glm::vec3> wos;
  for (float theta : {0.0f, 0.6f, 1.2f, 1.5f}) {
    wos.push_back(spherical(theta, 0.5f));
    if (below) wos.push_back(spherical(kPi - theta, 0.5f));
  }
  return wos;
}

}  // namespace tessera::test
