// Mitsuba 3's `hair` (src/bsdfs/hair.cpp): the near-field fibre model of Chiang, Bitterli,
// Tappan and Burley, "A Practical and Controllable Hair and Fur Model for Production Path
// Tracing" (2016), as pbrt-v4's HairBxDF: reflection R (p = 0), transmission TT (1), TRT (2)
// and the rest summed (3), each a longitudinal lobe M_p (d'Eon et al. 2011) times an attenuation
// A_p (Fresnel and absorption along the path inside the fibre) times an azimuthal trimmed
// logistic N_p, with the cuticle's scales tilting the lobes.
//
// Local frame (Mitsuba's shading frame on a curve): +x = the direction around the fibre (dp/du),
// +y = along the fibre, +z = the surface normal. The fibre offset h in [-1, 1] at which the
// light enters comes from wo's position around the fibre, as in Mitsuba: the BSDF is meant for
// curves (a hit's normal then says where across the fibre it is). A single scattering event
// stands for the whole walk through the fibre: wi may point anywhere on the sphere.
// The model is not reciprocal (Mitsuba flags it NonSymmetric: h and the scale tilt follow wo),
// so wo must be the direction towards the camera, Mitsuba's si.wi.
#pragma once

#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

/// d'Eon et al.'s longitudinal lobe as Mitsuba evaluates it (warp::square_to_rough_fiber_pdf
/// with the fibre along +y and kappa = 1 / v): a density over the sphere of directions wi
/// around wo, symmetric in its two directions. v > 0 is the lobe's variance; for v < 0.1 it is
/// evaluated in log space (Jakob's form), where exp(1 / v) would overflow.
float hair_longitudinal(glm::vec3 wi, glm::vec3 wo, float v);

class HairBsdf {
 public:
  explicit HairBsdf(const HairInputs& p);
  /// The BSDF of a hair material (p.type == MaterialType::hair): p.hair.
  explicit HairBsdf(const BsdfParams& p) : HairBsdf(p.hair) {}

  /// f(wo, wi) |cos| as Mitsuba's eval returns it (the model's sum over p of M_p A_p N_p).
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// u_lobe chooses p by the luminance of A_p and is reused (rescaled) for the azimuth; u
  /// draws the longitudinal angle and, for p = 3, the azimuth. nullopt at zero density.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

  static constexpr int kPMax = 3;

 private:
  /// The attenuation A_p of each path length p (3 = the sum of all longer ones) for wo.
  void attenuation(float cos_theta_o, float h, glm::vec3 transmittance,
                   glm::vec3 a_p[kPMax + 1]) const;
  /// The probability of choosing each p: A_p's luminance over their sum.
  void attenuation_pdf(glm::vec3 wo, float pdf[kPMax + 1]) const;
  /// sin and cos theta of wo tilted by the scales for path length p.
  void reframe(float sin_theta, float cos_theta, int p, float* sin_p, float* cos_p) const;
  /// The model's value and density for wi (either may be skipped with nullptr).
  void eval_pdf(glm::vec3 wo, glm::vec3 wi, glm::vec3* value, float* pdf) const;

  glm::vec3 sigma_a_{0.0f};
  float eta_ = 1.55f;
  float v_[kPMax + 1];  ///< longitudinal variances
  float s_ = 0;         ///< azimuthal logistic scale
  float sin_2k_alpha_[3], cos_2k_alpha_[3];
};

}  // namespace tessera
