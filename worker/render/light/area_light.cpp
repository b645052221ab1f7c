#include "render/light/area_light.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <utility>

#include "accum/accumulation.h"
#include "render/warp.h"

namespace tessera {

glm::vec2 sphere_uv(const glm::mat3& frame, glm::vec3 dir) {
  const glm::vec3 local = glm::transpose(frame) * dir;
  float phi = std::atan2(local.y, local.x);
  if (phi < 0) phi += 2.0f * kPi;
  const float len = glm::length(local);
  const float cos_theta = len > 0 ? std::clamp(local.z / len, -1.0f, 1.0f) : 1.0f;
  return {phi * (0.5f * kInvPi), std::acos(cos_theta) * kInvPi};
}

AreaLight::AreaLight(const Geometry& g, TextureLookup textures)
    : g_(&g), textures_(std::move(textures)) {
  if (g.kind == Geometry::Kind::sphere) {
    area_ = float(4.0 * 3.14159265358979323846 * g.radius * g.radius);
    return;
  }
  std::vector<double> areas;
  areas.reserve(g.indices.size());
  double total = 0;
  for (const glm::u32vec3& tri : g.indices) {
    const glm::dvec3 p0(g.positions[tri.x]), p1(g.positions[tri.y]), p2(g.positions[tri.z]);
    areas.push_back(0.5 * glm::length(glm::cross(p1 - p0, p2 - p0)));
    total += areas.back();
  }
  triangles_ = PiecewiseConstant1D(areas);
  area_ = float(total);
}

AreaLight::PointSample AreaLight::sample_point(glm::vec2 u) const {
  const Geometry& g = *g_;
  PointSample s;
  if (g.kind == Geometry::Kind::sphere) {
    const glm::dvec3 dir(square_to_uniform_sphere(u));
    s.sp.p = glm::vec3(g.center + g.radius * dir);
    s.sp.p_error = gamma_bound(5) * glm::abs(s.sp.p);
    s.sp.ng = glm::vec3(g.inward ? -dir : dir);
    s.uv = sphere_uv(g.frame, glm::vec3(dir));
    return s;
  }
  // A triangle by area, then the remainder of u.x inside its interval, so that the
  // stratification of u carries over to the point on the triangle.
  float pmf = 0, ux = 0;
  const uint32_t i = triangles_.sample_discrete(u.x, &pmf, &ux);
  const glm::vec2 b = square_to_triangle({ux, u.y});
  const float b0 = 1.0f - b.x - b.y;
  const glm::u32vec3 tri = g.indices[i];
  s.sp.p = b0 * g.positions[tri.x] + b.x * g.positions[tri.y] + b.y * g.positions[tri.z];
  s.sp.p_error = glm::vec3(g.point_errors[i]);
  s.sp.ng = g.face_normals[i];
  if (!g.uvs.empty()) s.uv = b0 * g.uvs[tri.x] + b.x * g.uvs[tri.y] + b.y * g.uvs[tri.z];
  return s;
}

LightSample AreaLight::sample(glm::vec3 ref, glm::vec2 u) const {
  LightSample s;
  if (!(area_ > 0)) return s;
  const PointSample ps = sample_point(u);
  const glm::vec3 to_light = ps.sp.p - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0)) return s;
  const float distance = std::sqrt(dist2);
  const glm::vec3 wi = to_light / distance;
  const float cos_light = std::abs(glm::dot(ps.sp.ng, wi));
  const glm::vec3 le = emitted(ps.uv, ps.sp.ng, -wi);
  if (!(cos_light > 0) || le == glm::vec3(0.0f)) return s;
  s.wi = wi;
  s.distance = distance;
  s.radiance = le;
  s.pdf = dist2 / (cos_light * area_);
  s.point = ps.sp;
  return s;
}

glm::vec3 AreaLight::emitted(glm::vec2 uv, glm::vec3 ng, glm::vec3 w) const {
  const Geometry& g = *g_;
  if (!(glm::dot(ng, w) > 0) && !g.two_sided_emission) return glm::vec3(0.0f);
  if (g.emission_texture < 0) return g.emission;
  return g.emission * textures_(g.emission_texture, uv);
}

float AreaLight::pdf(glm::vec3 ref, glm::vec3 hit_p, glm::vec3 hit_ng) const {
  const glm::vec3 to_light = hit_p - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0) || !(area_ > 0)) return 0.0f;
  const float cos_light = std::abs(glm::dot(hit_ng, to_light)) / std::sqrt(dist2);
  if (!(cos_light > 0)) return 0.0f;
  return dist2 / (cos_light * area_);
}

double AreaLight::power() const {
  const Geometry& g = *g_;
  glm::dvec3 radiance(g.emission);
  if (g.emission_texture >= 0) {
    constexpr int kProbes = 16;
    glm::dvec3 sum(0.0);
    for (int y = 0; y < kProbes; ++y) {
      for (int x = 0; x < kProbes; ++x) {
        const glm::vec2 uv((float(x) + 0.5f) / kProbes, (float(y) + 0.5f) / kProbes);
        sum += glm::dvec3(textures_(g.emission_texture, uv));
      }
    }
    const glm::dvec3 mean = sum / double(kProbes * kProbes);
    if (luminance(mean.x, mean.y, mean.z) > 0) radiance *= mean;
  }
  const double sides = g.two_sided_emission ? 2.0 : 1.0;
  return luminance(radiance.x, radiance.y, radiance.z) * double(area_) * double(kPi) * sides;
}

}  // namespace tessera
