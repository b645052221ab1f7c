#include "render/light/emitter.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/warp.h"

namespace tessera {
namespace {

float luminance(glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// Index of the first cdf entry above u (cdf ascending, last = 1).
uint32_t find_interval(const std::vector<float>& cdf, float u) {
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  return uint32_t(std::min<size_t>(size_t(it - cdf.begin()), cdf.size() - 1));
}

}  // namespace

Emitter::Emitter(const Geometry& geometry) : geometry_(&geometry) {
  if (geometry.kind == Geometry::Kind::sphere) {
    area_ = float(4.0 * 3.14159265358979323846 * geometry.radius * geometry.radius);
    return;
  }
  double total = 0;
  std::vector<double> cumulative;
  cumulative.reserve(geometry.indices.size());
  for (const glm::u32vec3& tri : geometry.indices) {
    const glm::dvec3 p0(geometry.positions[tri.x]), p1(geometry.positions[tri.y]),
        p2(geometry.positions[tri.z]);
    total += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
    cumulative.push_back(total);
  }
  area_ = float(total);
  triangle_cdf_.reserve(cumulative.size());
  for (double c : cumulative) triangle_cdf_.push_back(float(c / total));
  triangle_cdf_.back() = 1.0f;
}

float Emitter::power() const {
  const float sides = geometry_->two_sided_emission ? 2.0f : 1.0f;
  return luminance(geometry_->emission) * area_ * kPi * sides;
}

EmitterSample Emitter::sample(glm::vec2 u) const {
  const Geometry& g = *geometry_;
  EmitterSample s;
  s.pdf_area = 1.0f / area_;
  if (g.kind == Geometry::Kind::sphere) {
    const glm::dvec3 dir(square_to_uniform_sphere(u));
    const glm::dvec3 p = g.center + g.radius * dir;
    s.sp.p = glm::vec3(p);
    s.sp.p_error = gamma_bound(5) * glm::abs(s.sp.p);
    s.sp.ng = glm::vec3(g.inward ? -dir : dir);
    return s;
  }
  // Choose a triangle by area, then reuse the remainder of u.x inside its interval so the
  // stratification of u carries over to the point on the triangle.
  const uint32_t i = find_interval(triangle_cdf_, u.x);
  const float lo = i == 0 ? 0.0f : triangle_cdf_[i - 1];
  const float width = triangle_cdf_[i] - lo;
  const float ux = width > 0 ? std::min((u.x - lo) / width, 0x1.fffffep-1f) : 0.0f;
  const glm::vec2 b = square_to_triangle({ux, u.y});
  const glm::u32vec3 tri = g.indices[i];
  const glm::vec3 p0 = g.positions[tri.x], p1 = g.positions[tri.y], p2 = g.positions[tri.z];
  const float b0 = 1.0f - b.x - b.y;
  s.sp.p = b0 * p0 + b.x * p1 + b.y * p2;
  s.sp.p_error = glm::vec3(g.point_errors[i]);
  s.sp.ng = g.face_normals[i];
  return s;
}

LightSelector::LightSelector(const std::vector<Emitter>& emitters) {
  double total = 0;
  for (const Emitter& e : emitters) total += double(e.power());
  double running = 0;
  for (const Emitter& e : emitters) {
    const double p = total > 0 ? double(e.power()) / total : 1.0 / double(emitters.size());
    running += p;
    pmf_.push_back(float(p));
    cdf_.push_back(float(running));
  }
  if (!cdf_.empty()) cdf_.back() = 1.0f;
}

uint32_t LightSelector::pick(float u, float* pmf) const {
  uint32_t i = find_interval(cdf_, u);
  // Skip emitters with zero probability that float rounding could land on.
  while (pmf_[i] == 0.0f && i + 1 < pmf_.size()) ++i;
  *pmf = pmf_[i];
  return i;
}

}  // namespace tessera
