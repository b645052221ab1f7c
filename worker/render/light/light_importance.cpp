#include "render/light/light_importance.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace tessera {
namespace {

// GCC's vector extensions: +, -, *, / and comparisons lane by lane, IEEE in every lane, on
// whatever vector unit the target has (or none). -ffp-contract=off keeps a * b + c two
// roundings, as in the scalar code.
using Float4 = float __attribute__((vector_size(16)));
using Mask4 = int32_t __attribute__((vector_size(16)));

Float4 load(const float* v) {
  Float4 r;
  std::memcpy(&r, v, sizeof r);
  return r;
}
Mask4 load(const int32_t* v) {
  Mask4 r;
  std::memcpy(&r, v, sizeof r);
  return r;
}
Float4 splat(float x) { return Float4{x, x, x, x}; }

/// Correctly rounded in every lane (sqrtps, or the scalar sqrt lane by lane): the same bits.
Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
  return _mm_sqrt_ps(x);
#else
  return Float4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
Float4 abs4(Float4 x) {
  Mask4 bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits &= 0x7fffffff;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}
/// max(x, lo) lane by lane; lo where x is NaN.
Float4 at_least(Float4 x, Float4 lo) { return x > lo ? x : lo; }
/// min(x, hi) lane by lane.
Float4 at_most(Float4 x, Float4 hi) { return x < hi ? x : hi; }

/// The importance of the block's four lights at p (normal n, has_n: n != 0). Written once,
/// called by evaluate_all and evaluate alike, so a lane's bits never depend on the caller.
[[gnu::always_inline]] inline Float4 block_importance(const LightImportance::Block& b, Float4 px,
                                                      Float4 py, Float4 pz, Float4 nx, Float4 ny,
                                                      Float4 nz, bool has_n) {
  const Float4 zero = splat(0.0f), one = splat(1.0f);
  const Float4 dx = px - load(b.cx), dy = py - load(b.cy), dz = pz - load(b.cz);
  const Float4 d2 = dx * dx + dy * dy + dz * dz;
  const Float4 r2 = load(b.radius2);
  const Float4 inv_dist = one / sqrt4(d2);
  // theta_b: the half-angle the bounding sphere subtends at p.
  const Float4 sin_b = load(b.radius) * inv_dist;
  const Float4 cos_b = sqrt4(at_least(d2 - r2, zero)) * inv_dist;

  // At the light: theta_x = max(0, theta_w - theta_o), the smallest angle between a normal and
  // the direction to p's centre, then minus theta_b, compared with theta_e.
  Float4 cos_w = (load(b.wx) * dx + load(b.wy) * dy + load(b.wz) * dz) * inv_dist;
  cos_w = load(b.two_sided) ? abs4(cos_w) : cos_w;
  const Float4 cos_o = load(b.cos_o), sin_o = load(b.sin_o);
  const Float4 sin_w = sqrt4(at_least(one - cos_w * cos_w, zero));
  const Mask4 outside_cone = cos_w < cos_o;
  const Float4 cos_x = outside_cone ? cos_w * cos_o + sin_w * sin_o : one;
  const Float4 sin_x = outside_cone ? sin_w * cos_o - cos_w * sin_o : zero;
  const Float4 cos_light = cos_x >= cos_b ? one : cos_x * cos_b + sin_x * sin_b;
  Float4 importance = load(b.phi) * cos_light / d2;

  // At p: the smallest angle between its normal (either side) and a direction to the light.
  if (has_n) {
    const Float4 cos_i = abs4((nx * dx + ny * dy + nz * dz) * inv_dist);
    const Float4 sin_i = sqrt4(at_least(one - cos_i * cos_i, zero));
    const Float4 cos_p = cos_i >= cos_b ? one : cos_i * cos_b + sin_i * sin_b;
    importance *= at_least(cos_p, splat(1e-3f));
  }
  importance = at_most(at_least(importance, load(b.min_importance)),
                       splat(LightImportance::kMaxImportance));
  // Unreachable only where the bound says so by more than float rounding (cos_e holds
  // cos theta_e - kReachSlack); a NaN (from an infinite distance) reaches.
  const Mask4 unreachable = cos_light <= load(b.cos_e);
  importance = unreachable ? zero : importance;
  // Inside the bounds there is no angle to bound (lights at infinity: always inside).
  return d2 <= r2 ? load(b.inside) : importance;
}

float clamp_importance(double importance, double min) {
  return float(std::clamp(importance, min, double(LightImportance::kMaxImportance)));
}

}  // namespace

LightImportance::LightImportance(const std::vector<LightBounds>& bounds)
    : count_(uint32_t(bounds.size())) {
  if (bounds.size() > kMaxLights) {
    throw std::invalid_argument("LightImportance: " + std::to_string(bounds.size()) +
                                " lights, at most " + std::to_string(kMaxLights));
  }
  double max_phi = 0;
  for (const LightBounds& lb : bounds) max_phi = std::max(max_phi, lb.phi);
  const double scale = max_phi > 0 ? 1.0 / max_phi : 1.0;

  block_count_ = uint32_t((bounds.size() + kLanes - 1) / kLanes);
  for (Block& b : blocks_) {
    // Padding: never inside (radius2 < 0), never reached (cos_e > 1), power 0.
    for (size_t k = 0; k < kLanes; ++k) {
      b.cx[k] = b.cy[k] = b.cz[k] = 0;
      b.radius[k] = 0;
      b.radius2[k] = -1;
      b.phi[k] = b.inside[k] = b.min_importance[k] = 0;
      b.wx[k] = b.wy[k] = 0;
      b.wz[k] = 1;
      b.cos_o[k] = -1;
      b.sin_o[k] = 0;
      b.cos_e[k] = 2;
      b.two_sided[k] = 0;
    }
  }
  for (size_t i = 0; i < bounds.size(); ++i) {
    const LightBounds& lb = bounds[i];
    Block& b = blocks_[i / kLanes];
    const size_t k = i % kLanes;
    const double phi = lb.phi * scale;
    const double min = phi > 0 ? double(kMinImportance) : 0.0;
    b.min_importance[k] = float(min);
    b.phi[k] = float(phi);
    b.cos_e[k] = lb.cos_theta_e - kReachSlack;
    if (lb.infinite) {
      b.radius[k] = b.radius2[k] = std::numeric_limits<float>::infinity();
      b.inside[k] = clamp_importance(phi, min);
      continue;
    }
    b.cx[k] = lb.center.x;
    b.cy[k] = lb.center.y;
    b.cz[k] = lb.center.z;
    const double r = lb.radius;
    b.radius[k] = lb.radius;
    b.radius2[k] = float(r * r);
    b.inside[k] = clamp_importance(phi / std::max(r * r, 1e-20), min);
    b.wx[k] = lb.w.x;
    b.wy[k] = lb.w.y;
    b.wz[k] = lb.w.z;
    const double cos_o = lb.cos_theta_o;
    b.cos_o[k] = lb.cos_theta_o;
    b.sin_o[k] = float(std::sqrt(std::max(0.0, 1.0 - cos_o * cos_o)));
    b.two_sided[k] = lb.two_sided ? -1 : 0;
  }
}

float LightImportance::evaluate_all(const glm::vec3& p, const glm::vec3& n,
                                    float* importance) const {
  const bool has_n = n.x != 0 || n.y != 0 || n.z != 0;  // else a point in a medium
  if (block_count_ != 1) return evaluate_blocks(p, n, has_n, importance);
  // Up to four lights (the benchmark scenes): one block, no loop, nothing kept on the stack.
  const Float4 v = block_importance(blocks_[0], splat(p.x), splat(p.y), splat(p.z), splat(n.x),
                                    splat(n.y), splat(n.z), has_n);
  std::memcpy(importance, &v, sizeof v);
  float sum = 0;
  for (uint32_t i = 0; i < count_; ++i) sum += v[i];
  return sum;
}

float LightImportance::evaluate_blocks(const glm::vec3& p, const glm::vec3& n, bool has_n,
                                       float* importance) const {
  const Float4 px = splat(p.x), py = splat(p.y), pz = splat(p.z);
  const Float4 nx = splat(n.x), ny = splat(n.y), nz = splat(n.z);
  for (uint32_t j = 0; j < block_count_; ++j) {
    const Float4 v = block_importance(blocks_[j], px, py, pz, nx, ny, nz, has_n);
    std::memcpy(importance + j * kLanes, &v, sizeof v);
  }
  float sum = 0;
  for (uint32_t i = 0; i < count_; ++i) sum += importance[i];
  return sum;
}

float LightImportance::evaluate(uint32_t i, const glm::vec3& p, const glm::vec3& n) const {
  const bool has_n = n.x != 0 || n.y != 0 || n.z != 0;
  const Float4 v = block_importance(blocks_[i / kLanes], splat(p.x), splat(p.y), splat(p.z),
                                    splat(n.x), splat(n.y), splat(n.z), has_n);
  return v[i % kLanes];
}

}  // namespace tessera
