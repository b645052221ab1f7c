// The one-sample mixture of bounce directions at a diffuse vertex: cosine-weighted, or uniform
// in the cone of one of the scene's specular targets or of a lamp's image in one
// (specular_targets.h; docs/renderer.md, "Bounces toward glass and mirrors" and "Bounces aimed
// at the lamps' images"). Inlined into path_vertex (path_vertex.h), so the scalar
// integrator and every wavefront kernel run the same arithmetic.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/guiding/specular_targets.h"
#include "render/math/float4.h"
#include "render/math/frame.h"
#include "render/sampling/warp.h"

namespace tessera {

// init_lanes passes 8-lane vectors between inlined functions only (float4.h): GCC's note that
// their ABI would differ without AVX does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

/// A direction uniform in the cone around unit `axis` whose half-angle has 1 - cos theta_max =
/// one_minus_cos_max (solid angle density 1 / (2 pi one_minus_cos_max)), from u in [0, 1)^2:
/// the concentric disk's point (x, y) at radius r gives 1 - cos theta = r^2 (1 - cos theta_max)
/// (uniform in the cap, as r^2 is uniform) and the azimuth of (x, y), so sin theta (x, y) / r =
/// (x, y) sqrt((1 - cos theta_max)(2 - r^2 (1 - cos theta_max))): no sine, cosine or division.
[[gnu::always_inline]] inline glm::vec3 sample_uniform_cone(glm::vec3 axis, float one_minus_cos_max, glm::vec2 u) {
  const glm::vec2 disk = square_to_concentric_disk(u);
  const float one_minus_cos = glm::dot(disk, disk) * one_minus_cos_max;
  const float scale = std::sqrt(std::max(0.0f, one_minus_cos_max * (2.0f - one_minus_cos)));
  const glm::vec3 local(disk.x * scale, disk.y * scale, 1.0f - one_minus_cos);
  return Frame(axis).to_world(local);
}

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
  ///
  /// Four targets or images per vector operation here (baseline code, called by the scalar
  /// integrator and the tests); the AVX2 and AVX-512 wavefront kernels call init_lanes with
  /// eight (wavefront_kernel.inc). The same bits either way.
  bool init(const SpecularTargets& targets, glm::vec3 p, glm::vec3 n) {
    return init_lanes<float4::Float4, float4::Mask4>(targets, p, n);
  }

  /// init, kWidth<V> targets or images per operation of the float vector type V (M: its mask
  /// type, int32 lanes). Inlined where it is called, so compiled for the caller's instruction
  /// set.
  template <class V, class M>
  [[gnu::always_inline]] bool init_lanes(const SpecularTargets& targets, glm::vec3 p, glm::vec3 n) {
    // At every diffuse vertex of a scene with targets, so kept cheap: a target's or an image's
    // every test computed lane-wise, and its cone kept where all of them pass, in the order of
    // the scalar loop it replaces (the cone's numbers are the same operations on the same
    // values, so the same bits: SpecularTargets.ConesFourAtATimeAreTheScalarLoopsBits; the
    // scalar loop's branches cost hexroom 827 instructions a call, BENCHMARKS.md, "Instructions
    // per sample"). r^2 precomputed per scene, one square root and one division
    // for the axis, and no division for the density (p_k / solid_angle_k reduces to
    // kMassFactor cos(axis) scale / pi).
    using namespace float4;
    constexpr int W = kWidth<V>;
    static_assert(SpecularTargets::kMaxTargets % W == 0 &&
                  W <= SpecularTargets::kSourceLanes - SpecularTargets::kMaxSources);
    count_ = 0;
    float sum_p = 0;
    const V px = splat_lanes<V>(p.x), py = splat_lanes<V>(p.y), pz = splat_lanes<V>(p.z);
    const V nx = splat_lanes<V>(n.x), ny = splat_lanes<V>(n.y), nz = splat_lanes<V>(n.z);
    const V one = splat_lanes<V>(1.0f);
    // Mass times cos(axis) per cone (the density's first factor), and q_k.
    float mass_cos[kMaxCones + kAppendRoom];
    float q[kMaxCones + kAppendRoom];
    // The targets, then the images. A target's cone has a shorter formula (no gate, no window,
    // never turned), but an image's covers it (a target is an image of itself:
    // SpecularTargets::ConeSources): where all fit one block (cornell-sphere: 2 targets and 2
    // images in one block of eight) they go through the image's formula together, else the
    // targets through their own and the images after them (hexroom: 3 targets, then 8 images).
    const SpecularTargets::ConeSources& c = targets.cone_sources();
    if (c.count <= W) {
      source_block<V, M, true>(c, 0, px, py, pz, nx, ny, nz, mass_cos, q, &sum_p);
    } else {
      const SpecularTargets::Lanes& t = targets.lanes();
      for (int b = 0; b < targets.size(); b += W) {
        const V dx = load_lanes<V>(t.cx + b) - px, dy = load_lanes<V>(t.cy + b) - py, dz = load_lanes<V>(t.cz + b) - pz;
        // The centre on or below the horizon (at least half the cone below it), or p inside the
        // sphere (lanes past size() have r^2 = infinity): no cone.
        const V dn = (dx * nx + dy * ny) + dz * nz;
        const V dist2 = (dx * dx + dy * dy) + dz * dz;
        const V r2 = load_lanes<V>(t.r2 + b);
        const V inv_dist = one / sqrt_lanes(dist2);
        const V sin2 = one < r2 * (inv_dist * inv_dist) ? one : r2 * (inv_dist * inv_dist);  // std::min(x, 1)
        // 1 - cos theta_max = sin^2 / (1 + cos): no cancellation for small cones.
        const V one_minus_cos = sin2 / (one + sqrt_lanes(one - sin2));
        const V cos_axis = dn * inv_dist;
        // q_k = 2 pi (1 - cos theta_max) cos(axis) / pi; a cone too small for float (q_k = 0)
        // is never chosen, so never counted.
        const V qk = SpecularTargets::kMassFactor * ((2.0f * one_minus_cos) * cos_axis);
        const M keep = (dn > 0.0f) & (dist2 > r2) & (qk > 0.0f);
        append<V, M>(bits_of_lanes(keep), dx * inv_dist, dy * inv_dist, dz * inv_dist, one_minus_cos,
               SpecularTargets::kMassFactor * cos_axis, qk, mass_cos, q, &sum_p);
      }
      for (int b = targets.size(); b < c.count; b += W) {
        source_block<V, M, false>(c, b, px, py, pz, nx, ny, nz, mass_cos, q, &sum_p);
      }
    }
    if (count_ == 0) return false;
    const float scale = sum_p > SpecularTargets::kMaxTargetProbability
                            ? SpecularTargets::kMaxTargetProbability / sum_p
                            : 1.0f;
    // p_k / solid_angle_k = mass_k 2 (1 - cos) cos(axis) scale / (2 pi (1 - cos)).
    const float density_factor = kInvPi * scale;
    float cdf = 0;
    for (int k = 0; k < count_; ++k) {
      cdf += q[k] * scale;
      cdf_[k] = cdf;
      density_[k] = mass_cos[k] * density_factor;
    }
    // pdf() reads four cones at a time: the four lanes after the last are in no cone (their
    // axis 0, cos theta_max 2) and of density 0.
    const Float4 zero = splat(0.0f), two = splat(2.0f);
    std::memcpy(axis_x_ + count_, &zero, sizeof zero);
    std::memcpy(axis_y_ + count_, &zero, sizeof zero);
    std::memcpy(axis_z_ + count_, &zero, sizeof zero);
    std::memcpy(cos_max_ + count_, &two, sizeof two);
    std::memcpy(density_ + count_, &zero, sizeof zero);
    p_targets_ = cdf;
    p_cosine_ = 1.0f - cdf;
    return true;
  }

  /// The strategy of u_strategy in [0, 1): a cone's index, or -1 for the cosine.
  int choose(float u_strategy) const {
    if (u_strategy >= p_targets_) return -1;
    for (int k = 0; k + 1 < count_; ++k) {
      if (u_strategy < cdf_[k]) return k;
    }
    return count_ - 1;
  }

  /// A direction uniform in cone k (solid angle density 1 / solid_angle_k), from u in [0, 1)^2
  /// (sample_uniform_cone).
  glm::vec3 sample_cone(int k, glm::vec2 u) const {
    return sample_uniform_cone(glm::vec3(axis_x_[k], axis_y_[k], axis_z_[k]), one_minus_cos_[k], u);
  }

  /// pdf(w) for a unit w with cos_n = dot(w, n). `sampled_cone`: the cone w was drawn from
  /// (counted as holding w whatever rounding says of its edge), or -1.
  ///
  /// Four cones per vector operation; their densities are added in cone order, 0 for a cone
  /// that does not hold w (x + 0 = x for the non-negative sums here), so the same bits as
  /// adding only the holding ones.
  float pdf(glm::vec3 w, float cos_n, int sampled_cone = -1) const {
    using namespace float4;
    float pdf = cos_n > 0 ? p_cosine_ * (cos_n * kInvPi) : 0.0f;
    const Float4 wx = splat(w.x), wy = splat(w.y), wz = splat(w.z);
    const Mask4 lane = {0, 1, 2, 3};
    for (int b = 0; b < count_; b += 4) {
      const Float4 cos_w = (wx * load(axis_x_ + b) + wy * load(axis_y_ + b)) + wz * load(axis_z_ + b);
      const Mask4 holds = (cos_w >= load(cos_max_ + b)) | (lane + b == sampled_cone);
      const Float4 density = holds ? load(density_ + b) : splat(0.0f);
      pdf += density[0];
      pdf += density[1];
      pdf += density[2];
      pdf += density[3];
    }
    return pdf;
  }

  int count() const { return count_; }

 private:
  static constexpr int kMaxCones = SpecularTargets::kMaxTargets + SpecularTargets::kMaxImages;
  /// Room past the last cone: pdf() reads four cones at a time, append() stores eight lanes.
  static constexpr int kAppendRoom = 8;

  /// init_lanes for the sources b .. b + kWidth<V> - 1 of `c` (lanes past c.count have no
  /// cone): an image's cone, or a target's through the same formula. kTargets: whether the
  /// block may hold targets (else their `always` and mass need not be read).
  template <class V, class M, bool kTargets>
  [[gnu::always_inline]] void source_block(const SpecularTargets::ConeSources& c, int b, V px, V py, V pz, V nx,
                                           V ny, V nz, float* mass_cos, float* q, float* sum_p) {
    using namespace float4;
    const V one = splat_lanes<V>(1.0f);
    const M always = kTargets ? load_lanes<M>(c.always + b) : M{};
    // The wrong side of the target (lanes past the last have gate_offset = +infinity).
    const M gate = (((load_lanes<V>(c.gx + b) * px + load_lanes<V>(c.gy + b) * py) + load_lanes<V>(c.gz + b) * pz) >
                    load_lanes<V>(c.gate_offset + b)) |
                   always;
    // No early return where no lane passes the gate: a block with targets always has one,
    // and hexroom's eight images nearly always (measured: one more test than it saves).
    V dx = load_lanes<V>(c.cx + b) - px, dy = load_lanes<V>(c.cy + b) - py, dz = load_lanes<V>(c.cz + b) - pz;
    const V ex = load_lanes<V>(c.wx + b) - px, ey = load_lanes<V>(c.wy + b) - py, ez = load_lanes<V>(c.wz + b) - pz;
    // The light comes from the target: when the image lies behind p as seen from it (a real
    // image beyond p), the direction is toward the point 2p - I (never for a target: e = d).
    const M behind = ((dx * ex + dy * ey) + dz * ez) < 0.0f;
    dx = behind ? -dx : dx;
    dy = behind ? -dy : dy;
    dz = behind ? -dz : dz;
    const V dn = (dx * nx + dy * ny) + dz * nz;
    const V dist2 = (dx * dx + dy * dy) + dz * dz;
    const V r2 = load_lanes<V>(c.r2 + b);
    const V inv_dist = one / sqrt_lanes(dist2);
    // The window: the line from p along d passes the target's sphere, widened by the image
    // cone's radius at the target's distance t (an image only).
    const V t_window = ((ex * dx + ey * dy) + ez * dz) * inv_dist;
    const V reach = load_lanes<V>(c.wr + b) + (load_lanes<V>(c.r + b) * t_window) * inv_dist;
    const M window = ((((ex * ex + ey * ey) + ez * ez) - t_window * t_window) <= reach * reach) | always;
    const V sin2 = one < r2 * (inv_dist * inv_dist) ? one : r2 * (inv_dist * inv_dist);  // std::min(x, 1)
    const V one_minus_cos = sin2 / (one + sqrt_lanes(one - sin2));
    const V cos_axis = dn * inv_dist;
    const V mass = kTargets ? load_lanes<V>(c.mass + b) : splat_lanes<V>(SpecularTargets::kImageMassFactor);
    const V qk = mass * ((2.0f * one_minus_cos) * cos_axis);
    // The centre on or below the horizon, p inside the sphere, or outside the window: no cone.
    const M keep = gate & (dn > 0.0f) & (dist2 > r2) & window & (qk > 0.0f);
    append<V, M>(bits_of_lanes(keep), dx * inv_dist, dy * inv_dist, dz * inv_dist, one_minus_cos, mass * cos_axis, qk,
           mass_cos, q, sum_p);
  }

  /// Appends the cones of the lanes set in `bits` (lane 0 first), with their axis (unit, toward
  /// the sphere's centre), 1 - cos theta_max, mass times cos(axis) and q_k; adds q_k to *sum_p.
  /// Eight lanes at a time (the AVX2 and AVX-512 kernels): each quantity's chosen lanes moved to
  /// the front by one permutation and the whole vector stored at the arrays' end (their room
  /// past kMaxCones), q_k added in cone order as the lane loop adds them, so the same bits;
  /// the lane loop that extracted each kept lane was about 3-4 % of hexroom's and
  /// cornell-sphere's samples in a `perf` profile (BENCHMARKS.md, "Cost per sample against
  /// Mitsuba's, by depth").
  template <class V, class M>
  [[gnu::always_inline]] void append(unsigned bits, V ax, V ay, V az, V one_minus_cos, V mass_cos, V qk,
                                     float* mass_cos_out, float* q_out, float* sum_p) {
    using namespace float4;
    if constexpr (kWidth<V> == 8) {
      if (bits == 0) return;
      const int k = count_;
      compress_store<V, M>(axis_x_ + k, ax, bits);
      compress_store<V, M>(axis_y_ + k, ay, bits);
      compress_store<V, M>(axis_z_ + k, az, bits);
      compress_store<V, M>(one_minus_cos_ + k, one_minus_cos, bits);
      compress_store<V, M>(cos_max_ + k, splat_lanes<V>(1.0f) - one_minus_cos, bits);
      compress_store<V, M>(mass_cos_out + k, mass_cos, bits);
      compress_store<V, M>(q_out + k, qk, bits);
      count_ += __builtin_popcount(bits);
      for (int c = k; c < count_; ++c) *sum_p += q_out[c];
      return;
    }
    for (; bits != 0; bits &= bits - 1) {
      const int l = __builtin_ctz(bits);
      const int k = count_++;
      axis_x_[k] = ax[l];
      axis_y_[k] = ay[l];
      axis_z_[k] = az[l];
      one_minus_cos_[k] = one_minus_cos[l];
      cos_max_[k] = 1.0f - one_minus_cos[l];
      mass_cos_out[k] = mass_cos[l];
      q_out[k] = qk[l];
      *sum_p += qk[l];
    }
  }

  // The cones as arrays, count_ of them (pdf() reads four at a time, up to 3 lanes past the
  // last cone: init sets them to no cone; append() may store up to 7 lanes past it).
  alignas(16) float axis_x_[kMaxCones + kAppendRoom], axis_y_[kMaxCones + kAppendRoom],
      axis_z_[kMaxCones + kAppendRoom];
  alignas(16) float cos_max_[kMaxCones + kAppendRoom];  ///< cos theta_max
  alignas(16) float density_[kMaxCones + kAppendRoom];  ///< p_k / solid_angle_k
  float one_minus_cos_[kMaxCones + kAppendRoom];        ///< 1 - cos theta_max
  float cdf_[kMaxCones];                  ///< p_0 + ... + p_k
  int count_ = 0;
  float p_targets_ = 0, p_cosine_ = 1;
};

#pragma GCC diagnostic pop

}  // namespace tessera
