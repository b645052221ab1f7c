// The BSDF of one material at one shading point: Mitsuba 3's diffuse, conductor, roughconductor,
// dielectric, roughdielectric, thindielectric, plastic, roughplastic, pplastic, principled,
// principledthin, polarizer, hair and blendbsdf behind one interface
// (docs/renderer.md, "BSDFs").
//
// All directions are unit vectors in the local shading frame (+z = the material's front, i.e.
// the shading normal of the front side), pointing away from the surface. wo (towards the
// camera) may lie on either side: one-sided materials (diffuse, conductors, plastics) are black
// when wo or wi is below the surface (cos <= 0), as in Mitsuba; the integrator makes a
// two-sided material by flipping the frame before calling. Dielectrics, principled materials
// that transmit, thin principled ones, polarizers and hair handle both sides.
// No method returns NaN or infinity for finite unit inputs.
#pragma once

#include <optional>
#include <variant>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf/blend.h"
#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/conductor.h"
#include "render/bsdf/dielectric.h"
#include "render/bsdf/diffuse.h"
#include "render/bsdf/hair.h"
#include "render/bsdf/plastic.h"
#include "render/bsdf/polarizer.h"
#include "render/bsdf/pplastic.h"
#include "render/bsdf/principled.h"
#include "render/bsdf/principled_thin.h"
#include "render/bsdf/rough_conductor.h"
#include "render/bsdf/rough_dielectric.h"
#include "render/bsdf/rough_plastic.h"
#include "render/bsdf/thin_dielectric.h"

namespace tessera {

class Bsdf {
 public:
  /// Cheap: no allocation except for a blend (its two nested BSDFs). rough_plastic needs
  /// p.rough_plastic (see rough_plastic.h).
  explicit Bsdf(const BsdfParams& p);

  /// f(wo, wi) |cos wi| of the non-delta lobes (radiance transport); 0 where undefined.
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  /// The solid-angle density with which sample() returns wi among its non-delta lobes
  /// (including the probability of choosing those lobes); 0 for delta-only materials.
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// Draws wi: u_lobe in [0, 1) chooses a lobe (reflect or refract), u in [0, 1)^2 the
  /// direction. nullopt when the path ends (wo below a one-sided surface, a sampled direction
  /// on the wrong side, zero density).
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  /// Any non-delta lobe: next-event estimation and MIS are worth doing.
  bool has_smooth_lobe() const;
  /// The factor on the caustic guide's share of this BSDF's bounces at wo (path_vertex.h,
  /// guided_material; any value in [0, 1] is unbiased, this one is for lower variance): 1 for
  /// diffuse; for plastic, rough plastic and principled the probability that sample() takes
  /// their diffuse lobe; for a rough conductor min(1, 2 alpha), alpha the geometric mean of its
  /// two (measured: docs/renderer.md, "Bounces along the caustics"); 0 for the others.
  float caustic_guide_share(glm::vec3 wo) const;

 private:
  std::variant<DiffuseBsdf, ConductorBsdf, RoughConductorBsdf, DielectricBsdf, RoughDielectricBsdf,
               ThinDielectricBsdf, PlasticBsdf, RoughPlasticBsdf, PrincipledBsdf, BlendBsdf,
               PrincipledThinBsdf, PPlasticBsdf, PolarizerBsdf, HairBsdf>
      impl_;
};

}  // namespace tessera
