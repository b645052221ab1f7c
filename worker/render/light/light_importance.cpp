#include "render/light/light_importance.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>


namespace tessera {
using namespace light_importance_detail;
namespace {

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
