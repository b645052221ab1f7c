// A material as the integrator reads it: the scene's Material with its constants in float and
// its textures by index, so that a hit only looks up what is textured.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

struct RoughPlasticTable;  // bsdf/rough_plastic.h

/// A colour parameter: constant * texture(uv) when texture >= 0, the constant otherwise.
struct RenderColor {
  glm::vec3 value{0.0f};
  int32_t texture = -1;
};
struct RenderFloat {
  float value = 0;
  int32_t texture = -1;
};

struct RenderMaterial {
  MaterialType type = MaterialType::diffuse;
  glm::vec3 albedo{0.0f};  ///< diffuse reflectance when constant (the diffuse fast path's)
  float ior = 1.5f;        ///< glass kinds, plastics: interior over exterior
  bool two_sided = false;  ///< reflecting kinds: both sides reflect

  RenderColor reflectance;            ///< diffuse albedo, plastics' diffuse_reflectance
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

  /// rough_plastic: the material's precomputed Fresnel integrals (owned by TraceableScene).
  const RoughPlasticTable* rough_plastic = nullptr;

  /// Whether any parameter is a texture (the hit then needs its uv).
  bool textured = false;
  /// Glass kinds: both sides are the surface, with the index inverted from the back.
  bool dielectric() const {
    return type == MaterialType::glass || type == MaterialType::rough_glass ||
           type == MaterialType::thin_glass;
  }
  bool masked() const { return opacity.texture >= 0 || opacity.value < 1; }
};

/// The render form of `m`.
RenderMaterial make_render_material(const Material& m);

}  // namespace tessera
