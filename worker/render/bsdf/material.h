// A material as the integrator reads it: the scene's Material with its constants in float and
// its textures by index, so that a hit only looks up what is textured.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/texture/mesh_attribute_table.h"
#include "scene/scene.h"

namespace tessera {

struct RoughPlasticTable;   // bsdf/rough_plastic.h
class RoughPlasticTables;  // bsdf/rough_plastic_tables.h
class TextureSet;          // texture/texture_set.h

/// A colour parameter: constant * texture(uv) when texture >= 0, the constant otherwise.
struct RenderColor {
  glm::vec3 value{0.0f};
  int32_t texture = -1;
};
struct RenderFloat {
  float value = 0;
  int32_t texture = -1;
};

/// A principled (or principled_thin) material's parameters besides base_color and eta
/// (PrincipledParameters).
struct RenderPrincipled {
  RenderFloat roughness{0.5f, -1}, anisotropic, metallic, spec_trans, spec_tint, sheen, sheen_tint,
      flatness, clearcoat, clearcoat_gloss, diff_trans;
  float main_specular_sampling_rate = 1, clearcoat_sampling_rate = 1;
  float diffuse_reflectance_sampling_rate = 1;
  float specular_reflectance_sampling_rate = 1, specular_transmittance_sampling_rate = 1;
  float diffuse_transmittance_sampling_rate = 1;
  bool transmits = false;  ///< spec_trans textured or non-zero
};

/// A hair material's parameters besides its index (HairParameters).
struct RenderHair {
  RenderColor sigma_a;
  float longitudinal_roughness = 0.3f, azimuthal_roughness = 0.3f, scale_tilt_deg = 2;
};

struct RenderMaterial {
  MaterialType type = MaterialType::diffuse;
  glm::vec3 albedo{0.0f};  ///< diffuse reflectance when constant (the diffuse fast path's)
  float ior = 1.5f;        ///< glass kinds, plastics, principled: interior over exterior
  int32_t ior_texture = -1;  ///< principled_thin, pplastic: index = ior * texture(uv)
  bool two_sided = false;  ///< reflecting kinds: both sides reflect

  RenderColor reflectance;  ///< diffuse albedo, plastics' diffuse_reflectance, base_color
  RenderColor specular_reflectance;
  RenderColor specular_transmittance;
  glm::vec3 conductor_eta{0.0f}, conductor_k{1.0f};
  bool perfect = false;
  MicrofacetDistribution distribution = MicrofacetDistribution::beckmann;
  RenderFloat alpha_u, alpha_v;
  bool sample_visible = true;
  bool nonlinear = false;
  int32_t back = -1;         ///< material seen from the back (Mitsuba's twosided with two BSDFs)
  RenderFloat opacity{1, -1};
  int32_t normal_map = -1;
  int32_t bump_map = -1;
  float bump_scale = 1;

  /// rough_plastic: the material's precomputed Fresnel integrals (owned by the scene's
  /// RoughPlasticTables).
  const RoughPlasticTable* rough_plastic = nullptr;
  RenderPrincipled principled;  ///< principled only
  RenderFloat blend_weight{0.5f, -1};  ///< blend only
  std::vector<RenderMaterial> blend;   ///< blend only: the two nested materials
  RenderHair hair;                     ///< hair only

  /// Whether any parameter is a texture (the hit then needs its uv).
  bool textured = false;
  /// Glass kinds, principled materials that transmit, thin principled ones, polarizers and hair:
  /// both sides are the surface, with the index inverted from the back (the BSDF handles wo
  /// below the surface; hair takes wo and wi all around the fibre).
  bool dielectric() const {
    return type == MaterialType::glass || type == MaterialType::rough_glass ||
           type == MaterialType::thin_glass || type == MaterialType::principled_thin ||
           type == MaterialType::polarizer || type == MaterialType::hair ||
           (type == MaterialType::principled && principled.transmits) ||
           (type == MaterialType::blend && blend_transmits());
  }
  bool blend_transmits() const {
    for (const RenderMaterial& m : blend) {
      if (m.dielectric()) return true;
    }
    return false;
  }
  bool masked() const { return opacity.texture >= 0 || opacity.value < 1; }
};

/// The render form of `m`. Its rough plastics (nested in blends too) get their tables from
/// `tables`, which must outlive the result; throws SceneError when a rough plastic's alpha is
/// not one constant.
RenderMaterial make_render_material(const Material& m, RoughPlasticTables& tables);

/// The BSDF parameters of `m` at surface point `at`: constants as they are, textured parameters
/// looked up (only those of m's type; mesh attributes from at's shape).
BsdfParams bsdf_params(const RenderMaterial& m, const TextureSet& textures, const TexturePoint& at);

}  // namespace tessera
