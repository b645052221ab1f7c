// The inputs and outputs every BSDF of worker/render/bsdf/ shares: one material's parameters at
// one shading point (textures already looked up) and one sampled direction.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

struct RoughPlasticTable;  // rough_plastic.h

/// A principled (or principled_thin) material's parameters besides base_color and eta, looked
/// up at one shading point (core/scene/scene.h, PrincipledParameters, says what each means).
struct PrincipledInputs {
  float roughness = 0.5f, anisotropic = 0, metallic = 0, spec_trans = 0, spec_tint = 0;
  float sheen = 0, sheen_tint = 0, flatness = 0, clearcoat = 0, clearcoat_gloss = 0;
  float main_specular_sampling_rate = 1, clearcoat_sampling_rate = 1;
  float diffuse_reflectance_sampling_rate = 1;
  /// Mitsuba's m_has_spec_trans: the material transmits (spec_trans textured or non-zero).
  /// It changes the lobe probabilities seen from inside even where spec_trans is 0.
  bool transmits = false;
  /// principled_thin only: diff_trans in [0, 2] and the sampling rates of its other lobes.
  float diff_trans = 0;
  float specular_reflectance_sampling_rate = 1, specular_transmittance_sampling_rate = 1;
  float diffuse_transmittance_sampling_rate = 1;
};

/// A hair material's parameters at one shading point (HairParameters in core/scene/scene.h,
/// with sigma_a looked up and eta = Material::ior).
struct HairInputs {
  /// Absorption per unit fibre radius, >= 0 per channel: Mitsuba's scale * sigma_a, or
  /// melanin_sigma_a(eumelanin, pheomelanin).
  glm::vec3 sigma_a{0.0f};
  float eta = 1.55f;                    ///< interior / exterior index, > 0 and != 1
  float longitudinal_roughness = 0.3f;  ///< beta_m, in [0, 1]
  float azimuthal_roughness = 0.3f;     ///< beta_n, in [0, 1]
  float scale_tilt_deg = 2;             ///< alpha: the cuticle scales' angle, degrees
};

/// One material's BSDF parameters at one shading point, textures already looked up. The names
/// and meanings are Mitsuba 3's (core/scene/scene.h, docs/scenes.md).
struct BsdfParams {
  MaterialType type = MaterialType::diffuse;  ///< mirror = a perfect conductor
  glm::vec3 reflectance{0.5f};  ///< diffuse albedo; plastics' diffuse_reflectance; base_color
  glm::vec3 specular_reflectance{1.0f};
  glm::vec3 specular_transmittance{1.0f};
  /// dielectrics, plastics, principled: interior / exterior index, > 0; principled_thin: the
  /// sheet's index (light leaves it on the side it entered from: the path's index stays 1)
  float eta = 1.5f;
  glm::vec3 conductor_eta{0.0f}, conductor_k{1.0f};
  bool perfect = false;  ///< conductor material="none": Fresnel = 1
  MicrofacetDistribution distribution = MicrofacetDistribution::beckmann;
  float alpha_u = 0.1f, alpha_v = 0.1f;  ///< rough kinds, pplastic (rough_plastic: alpha_u)
  bool sample_visible = true;
  bool nonlinear = false;  ///< plastics
  /// rough_plastic only, required there: the material's precomputed Fresnel integrals
  /// (make_rough_plastic_table, once per material: they cost ~0.1 s). Not owned.
  const RoughPlasticTable* rough_plastic = nullptr;
  PrincipledInputs principled;  ///< principled and principled_thin only
  float blend_weight = 0.5f;    ///< blend only: the second BSDF's weight, in [0, 1]
  std::vector<BsdfParams> blend;  ///< blend only: the two nested BSDFs
  HairInputs hair;                ///< hair only (its eta is hair.eta, not eta)
};

/// One direction drawn by a BSDF.
struct BsdfSample {
  glm::vec3 wi{0.0f, 0.0f, 1.0f};  ///< unit, local frame
  /// f(wo, wi) |cos wi| / pdf for radiance transport (a transmission includes Mitsuba's
  /// 1 / eta^2 solid-angle compression factor).
  glm::vec3 weight{0.0f};
  /// Solid-angle density of the chosen lobe mix; for a delta lobe the discrete probability of
  /// choosing that lobe.
  float pdf = 0;
  bool delta = false;  ///< a perfectly specular lobe was sampled (no MIS, count emission)
  /// Relative index of the interface crossed (eta_t / eta_i); 1 for reflection.
  float eta = 1;
};

/// `s` if it is usable (finite direction, weight and pdf, pdf > 0), else empty: Bsdf::sample's
/// guard of the no-NaN contract, shared with path_vertex's shortcut for smooth specular
/// materials (specular_sample) so the two keep the same bits.
inline std::optional<BsdfSample> checked_sample(const std::optional<BsdfSample>& s) {
  const auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (s && (!finite(s->wi) || !finite(s->weight) || !std::isfinite(s->pdf) || !(s->pdf > 0.0f))) {
    return std::nullopt;
  }
  return s;
}

}  // namespace tessera
