// The anisotropic Beckmann and GGX microfacet distributions as Mitsuba 3 defines them
// (include/mitsuba/render/microfacet.h): alpha is the RMS slope (Beckmann) or the GGX width,
// per tangent axis; Smith's separable shadowing; sampling of all normals or of the visible ones.
#pragma once

#include <utility>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

class Microfacet {
 public:
  /// Mitsuba clamps alpha to 1e-4 so that the distribution stays representable in float.
  static constexpr float kMinAlpha = 1e-4f;

  Microfacet(MicrofacetDistribution type, float alpha_u, float alpha_v, bool sample_visible);

  MicrofacetDistribution type() const { return type_; }
  float alpha_u() const { return alpha_u_; }
  float alpha_v() const { return alpha_v_; }
  bool sample_visible() const { return sample_visible_; }
  /// Multiplies both alphas (Walter et al.'s widening of the sampling distribution).
  void scale_alpha(float s);

  /// The distribution of normals D(m), per unit projected area: the integral of D(m) cos(m)
  /// over the hemisphere is 1. 0 for m below the surface.
  float eval(glm::vec3 m) const;
  /// The density of sample(wi, .) over microfacet normals (solid angle).
  float pdf(glm::vec3 wi, glm::vec3 m) const;
  /// A microfacet normal m: distributed as D(m) cos(m) when !sample_visible, as the normals
  /// visible from wi (D(m) G1(wi, m) |wi.m| / cos(wi)) otherwise; wi must have wi.z > 0.
  /// Returns m and its density (0 when the sample is unusable).
  std::pair<glm::vec3, float> sample(glm::vec3 wi, glm::vec2 u) const;
  /// Smith's monodirectional shadowing of direction v by facets of normal m (0 when v sees
  /// the back of m relative to the macro surface).
  float smith_g1(glm::vec3 v, glm::vec3 m) const;
  /// The separable bidirectional shadowing-masking G1(wi) G1(wo).
  float G(glm::vec3 wi, glm::vec3 wo, glm::vec3 m) const {
    return smith_g1(wi, m) * smith_g1(wo, m);
  }

 private:
  glm::vec2 sample_visible_11(float cos_theta_i, glm::vec2 u) const;

  MicrofacetDistribution type_;
  float alpha_u_, alpha_v_;
  bool sample_visible_;
};

/// Inverse error function in float precision (Giles 2010, "Approximating the erfinv function").
float erfinv(float x);

}  // namespace tessera
