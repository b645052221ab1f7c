// The one-sample mixture of bounce directions at a diffuse vertex: cosine-weighted, or uniform
// in the cone of one of the scene's specular targets or of a lamp's image in one
// (specular_targets.h; docs/renderer.md, "Bounces toward glass and mirrors" and "Bounces aimed
// at the lamps' images"). Inlined into path_vertex (path_vertex.h), so the scalar
// integrator and every wavefront kernel run the same arithmetic.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "frame.h"
#include "specular_targets.h"
#include "warp.h"

namespace tessera {

/// The mixture at one diffuse point: with probability p_k, a direction uniform in the cone
/// subtended by target k; with probability 1 - sum p_k, a cosine-weighted one around the normal.
/// pdf(w) = (1 - sum p_k) cos / pi + sum_k p_k [w in cone k] / solid_angle_k (solid angle
/// density), so f cos / pdf weighs every strategy by the balance heuristic: unbiased wherever the
/// cosine strategy is, and never more than 1 / (1 - sum p_k) times the cosine sample's weight.
class TargetMixture {
 public:
  /// The cones of `targets` seen from `p` with unit normal `n`, and their probabilities: a
  /// target whose sphere holds p, or whose centre lies on or below n's horizon (the cone at
  /// least half below it), gets none. Returns whether any cone is left (the mixture is then
  /// used; else the vertex samples the cosine alone).
  ///
  /// The rule for p_k (docs/renderer.md, "Bounces toward glass and mirrors"): kMassFactor times
  /// the cone's share of the cosine strategy, q_k = solid_angle_k cos(axis) / pi, scaled down so
  /// that sum p_k <= kMaxTargetProbability. A small cone's density is so raised about
  /// (1 + kMassFactor)-fold at a cost of 1 / (1 - sum p_k) elsewhere, and sum p_k stays small
  /// where the targets are small; a cone the cosine already finds often gains less.
  ///
  /// Then each lamp image (SpecularTargets::images) whose gate p passes, which does not hold p,
  /// and whose line from p passes its window: a cone toward the image, or toward 2p - I when the
  /// image lies behind p as seen from the target, with p_k = mass q_k (the same cap).
  bool init(const SpecularTargets& targets, glm::vec3 p, glm::vec3 n) {
    // At every diffuse vertex of a scene with targets, so kept cheap (BENCHMARKS.md, "Cost per
    // sample, branch cost9"): the horizon test first, on the unnormalised direction (no square
    // root for a target behind the surface), r^2 precomputed per scene, one square root and one
    // division for the axis, and no division for the density (p_k / solid_angle_k reduces to
    // kMassFactor cos(axis) scale / pi).
    const SpecularTargets::Lanes& t = targets.lanes();
    count_ = 0;
    float sum_p = 0;
    const int size = targets.size();
    for (int i = 0; i < size; ++i) {
      const glm::vec3 d(t.cx[i] - p.x, t.cy[i] - p.y, t.cz[i] - p.z);
      const float dn = glm::dot(d, n);
      if (!(dn > 0)) continue;  // the centre on or below the horizon: at least half the cone below it
      const float dist2 = glm::dot(d, d);
      const float r2 = t.r2[i];
      if (!(dist2 > r2)) continue;  // p inside the sphere
      const float inv_dist = 1.0f / std::sqrt(dist2);
      const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
      // 1 - cos theta_max = sin^2 / (1 + cos): no cancellation for small cones.
      const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
      const float cos_axis = dn * inv_dist;
      // q_k = 2 pi (1 - cos theta_max) cos(axis) / pi.
      const float q = SpecularTargets::kMassFactor * (2.0f * one_minus_cos * cos_axis);
      if (!(q > 0)) continue;  // a cone too small for float: never chosen, so never counted
      Cone& c = cones_[count_++];
      c.axis = d * inv_dist;
      c.one_minus_cos = one_minus_cos;
      c.cos_max = 1.0f - one_minus_cos;
      c.cos_axis = cos_axis;
      c.mass = SpecularTargets::kMassFactor;
      c.p = q;
      sum_p += q;
    }
    const int images = targets.image_count();
    const SpecularImage* image = targets.images();
    for (int j = 0; j < images; ++j) {
      const SpecularImage& im = image[j];
      if (!(glm::dot(im.gate_normal, p) > im.gate_offset)) continue;  // the wrong side of the target
      glm::vec3 d = im.center - p;
      const glm::vec3 e = im.window_center - p;
      // The light comes from the target: when the image lies behind p as seen from it (a real
      // image beyond p), the direction is toward the point 2p - I.
      if (glm::dot(d, e) < 0) d = -d;
      const float dn = glm::dot(d, n);
      if (!(dn > 0)) continue;
      const float dist2 = glm::dot(d, d);
      const float r2 = im.radius * im.radius;
      if (!(dist2 > r2)) continue;  // p inside the image's sphere
      const float inv_dist = 1.0f / std::sqrt(dist2);
      // The window: the line from p along d passes the target's sphere, widened by the image
      // cone's radius at the target's distance t.
      const float t = glm::dot(e, d) * inv_dist;
      const float reach = im.window_radius + im.radius * t * inv_dist;
      if (!(glm::dot(e, e) - t * t <= reach * reach)) continue;
      const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
      const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
      const float cos_axis = dn * inv_dist;
      const float q = SpecularTargets::kImageMassFactor * (2.0f * one_minus_cos * cos_axis);
      if (!(q > 0)) continue;
      Cone& c = cones_[count_++];
      c.axis = d * inv_dist;
      c.one_minus_cos = one_minus_cos;
      c.cos_max = 1.0f - one_minus_cos;
      c.cos_axis = cos_axis;
      c.mass = SpecularTargets::kImageMassFactor;
      c.p = q;
      sum_p += q;
    }
    if (count_ == 0) return false;
    const float scale = sum_p > SpecularTargets::kMaxTargetProbability
                            ? SpecularTargets::kMaxTargetProbability / sum_p
                            : 1.0f;
    // p_k / solid_angle_k = mass_k 2 (1 - cos) cos(axis) scale / (2 pi (1 - cos)).
    const float density_factor = kInvPi * scale;
    float cdf = 0;
    for (int k = 0; k < count_; ++k) {
      Cone& c = cones_[k];
      cdf += c.p * scale;
      c.cdf = cdf;
      c.density = (c.mass * c.cos_axis) * density_factor;
    }
    p_targets_ = cdf;
    p_cosine_ = 1.0f - cdf;
    return true;
  }

  /// The strategy of u_strategy in [0, 1): a cone's index, or -1 for the cosine.
  int choose(float u_strategy) const {
    if (u_strategy >= p_targets_) return -1;
    for (int k = 0; k + 1 < count_; ++k) {
      if (u_strategy < cones_[k].cdf) return k;
    }
    return count_ - 1;
  }

  /// A direction uniform in cone k (solid angle density 1 / solid_angle_k), from u in [0, 1)^2:
  /// the concentric disk's point (x, y) at radius r gives 1 - cos theta = r^2 (1 - cos theta_max)
  /// (uniform in the cap, as r^2 is uniform) and the azimuth of (x, y), so sin theta (x, y) / r =
  /// (x, y) sqrt((1 - cos theta_max)(2 - r^2 (1 - cos theta_max))): no sine, cosine or division.
  glm::vec3 sample_cone(int k, glm::vec2 u) const {
    const Cone& c = cones_[k];
    const glm::vec2 disk = square_to_concentric_disk(u);
    const float one_minus_cos = glm::dot(disk, disk) * c.one_minus_cos;
    const float scale = std::sqrt(std::max(0.0f, c.one_minus_cos * (2.0f - one_minus_cos)));
    const glm::vec3 local(disk.x * scale, disk.y * scale, 1.0f - one_minus_cos);
    return Frame(c.axis).to_world(local);
  }

  /// pdf(w) for a unit w with cos_n = dot(w, n). `sampled_cone`: the cone w was drawn from
  /// (counted as holding w whatever rounding says of its edge), or -1.
  float pdf(glm::vec3 w, float cos_n, int sampled_cone = -1) const {
    float pdf = cos_n > 0 ? p_cosine_ * (cos_n * kInvPi) : 0.0f;
    for (int k = 0; k < count_; ++k) {
      if (k == sampled_cone || glm::dot(w, cones_[k].axis) >= cones_[k].cos_max) pdf += cones_[k].density;
    }
    return pdf;
  }

  int count() const { return count_; }

 private:
  struct Cone {
    glm::vec3 axis;       ///< unit, toward the sphere's centre
    float one_minus_cos;  ///< 1 - cos theta_max
    float cos_max;
    float cos_axis;       ///< cos of the axis to the normal
    float mass;           ///< the factor on the cone's share of the cosine strategy
    float p;              ///< p_k before scaling to sum p_k <= kMaxTargetProbability
    float cdf;            ///< p_0 + ... + p_k
    float density;        ///< p_k / solid_angle_k
  };
  Cone cones_[SpecularTargets::kMaxTargets + SpecularTargets::kMaxImages];
  int count_ = 0;
  float p_targets_ = 0, p_cosine_ = 1;
};

}  // namespace tessera
