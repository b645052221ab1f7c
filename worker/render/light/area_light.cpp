#include "render/light/area_light.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <utility>

#include "accum/accumulation.h"
#include "render/light/sphere_cone.h"
#include "render/light/spherical_rectangle.h"
#include "render/math/ray_offset.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

/// 1 / solid_angle as a float density; 0 where that overflows (a light too small to matter:
/// it is then neither sampled nor weighed against).
float inverse_solid_angle(double solid_angle) {
  const float pdf = float(1.0 / solid_angle);
  return solid_angle > 0 && std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace

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
    sampling_ = Sampling::sphere_cone;
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
  rectangle_ = find_rectangle(g);
  if (rectangle_) sampling_ = Sampling::rectangle;
}

std::optional<AreaLight::Rectangle> AreaLight::find_rectangle(const Geometry& g) {
  if (g.kind != Geometry::Kind::triangles || g.indices.size() != 2) return std::nullopt;
  // The two triangles must share two vertex positions (the diagonal); the other two are
  // opposite corners.
  const glm::u32vec3 a = g.indices[0], b = g.indices[1];
  int shared = 0;
  uint32_t a_only = 0, b_only = 0;
  bool a_shared[3] = {false, false, false}, b_shared[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!b_shared[j] && g.positions[a[i]] == g.positions[b[j]]) {
        a_shared[i] = b_shared[j] = true;
        ++shared;
        break;
      }
    }
  }
  if (shared != 2) return std::nullopt;
  for (int i = 0; i < 3; ++i) {
    if (!a_shared[i]) a_only = a[i];
    if (!b_shared[i]) b_only = b[i];
  }
  uint32_t diagonal[2];
  for (int i = 0, k = 0; i < 3; ++i) {
    if (a_shared[i]) diagonal[k++] = a[i];
  }
  Rectangle r;
  r.near = 0;
  r.far = 1;
  r.v_corner = a_only;
  r.v_opposite = b_only;
  r.v_x = diagonal[0];
  r.v_y = diagonal[1];
  r.corner = glm::dvec3(g.positions[a_only]);
  r.ex = glm::dvec3(g.positions[r.v_x]) - r.corner;
  r.ey = glm::dvec3(g.positions[r.v_y]) - r.corner;
  const double lx = glm::length(r.ex), ly = glm::length(r.ey);
  if (!(lx > 0) || !(ly > 0)) return std::nullopt;
  // A rectangle to within 1e-5 of its size (float vertices of a transformed rectangle are off by
  // about 1e-7): the density of the points it maps onto the triangles is then 1 / solid angle
  // to within about that much.
  constexpr double kTolerance = 1e-5;
  const glm::dvec3 closure = r.corner + r.ex + r.ey - glm::dvec3(g.positions[b_only]);
  if (std::abs(glm::dot(r.ex, r.ey)) > kTolerance * lx * ly ||
      glm::length(closure) > kTolerance * (lx + ly)) {
    return std::nullopt;
  }
  r.center = glm::vec3(r.corner + 0.5 * (r.ex + r.ey));
  // Rectangles are sampled by solid angle where the diagonal is at least the distance to the
  // centre (smaller, d^2 / cos varies too little over the light for the spherical rectangle's
  // cost to pay: measured on the Cornell box and hexroom, BENCHMARKS.md) and the point lies at
  // least 1e-5 diagonals off the plane (closer, the spherical-rectangle map loses accuracy in
  // double).
  const float diagonal_length = float(glm::length(r.ex + r.ey));
  r.diagonal = diagonal_length;
  r.diagonal2 = diagonal_length * diagonal_length;
  r.min_plane_distance = 1e-5f * diagonal_length;
  r.center_slack = 1e-6f * glm::length(r.center);
  // Both triangles facing the same side (else neither side is dark).
  r.one_sided = !g.two_sided_emission && glm::dot(g.face_normals[0], g.face_normals[1]) > 0;
  // On the emitting side: that of the face normals (which emitted() tests against).
  r.normal = glm::vec3(glm::normalize(glm::cross(r.ex, r.ey)));
  if (glm::dot(r.normal, g.face_normals[r.near]) < 0) r.normal = -r.normal;
  return r;
}

bool AreaLight::outside_sphere(glm::vec3 ref) const {
  // Clearly outside: a point on the sphere itself (the emitter's own surface, an enclosure's
  // inside) sees the sphere's far side, not the near cap the cone covers, and rounding may put
  // it a hair outside. Within the margin, area sampling is exact all the same.
  const Geometry& g = *g_;
  const glm::dvec3 d = glm::dvec3(ref) - g.center;
  const double c = glm::length(g.center);
  const double margin = 1e-3 * g.radius + 1e-5 * c;
  return glm::dot(d, d) > (g.radius + margin) * (g.radius + margin);
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
  // Uniform on the rectangle: corner + u.x ex + u.y ey has density 1 / |ex x ey|, which is
  // 1 / area_ to within find_rectangle's 1e-5 tolerance.
  if (rectangle_) return rectangle_point(u.x, u.y);
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

LightSample AreaLight::sample_solid_angle(glm::vec3 ref, glm::vec2 u) const {
  const Geometry& g = *g_;
  PointSample ps;
  float solid_angle_pdf = 0;
  if (sampling_ == Sampling::sphere_cone) {
    const SphereCone cone(glm::dvec3(ref), g.center, g.radius);
    const glm::dvec3 n = cone.sample_normal(u);
    ps.sp.p = glm::vec3(g.center + g.radius * n);
    ps.sp.p_error = gamma_bound(5) * glm::abs(ps.sp.p);
    ps.sp.ng = glm::vec3(g.inward ? -n : n);
    ps.uv = sphere_uv(g.frame, glm::vec3(n));
    solid_angle_pdf = inverse_solid_angle(cone.solid_angle());
  } else {
    const Rectangle& r = *rectangle_;
    const SphericalRectangle sr(glm::dvec3(ref), r.corner, r.ex, r.ey);
    solid_angle_pdf = inverse_solid_angle(sr.solid_angle());
    if (solid_angle_pdf > 0) {
      const glm::dvec2 ab = sr.sample(u);
      ps = rectangle_point(float(ab.x), float(ab.y));
    }
  }
  if (!(solid_angle_pdf > 0)) return {};
  return towards(ref, ps, solid_angle_pdf);
}

glm::vec3 AreaLight::textured_emission(glm::vec2 uv) const {
  const Geometry& g = *g_;
  return g.emission * textures_(g.emission_texture, uv);
}

float AreaLight::pdf(glm::vec3 ref, glm::vec3 hit_p, glm::vec3 hit_ng) const {
  if (!(area_ > 0) || behind(ref)) return 0.0f;
  if (solid_angle_sampled(ref)) {
    const Geometry& g = *g_;
    if (sampling_ == Sampling::sphere_cone) {
      return inverse_solid_angle(SphereCone(glm::dvec3(ref), g.center, g.radius).solid_angle());
    }
    const Rectangle& r = *rectangle_;
    return inverse_solid_angle(
        SphericalRectangle(glm::dvec3(ref), r.corner, r.ex, r.ey).solid_angle());
  }
  const glm::vec3 to_light = hit_p - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0) || !(area_ > 0)) return 0.0f;
  const float cos_light = std::abs(glm::dot(hit_ng, to_light)) / std::sqrt(dist2);
  if (!(cos_light > 0)) return 0.0f;
  return dist2 / (cos_light * area_);
}

LightBounds AreaLight::bounds() const {
  const Geometry& g = *g_;
  LightBounds b;
  b.phi = power();
  b.two_sided = g.two_sided_emission;
  if (g.kind == Geometry::Kind::sphere) {
    b.center = glm::vec3(g.center);
    b.radius = float(g.radius) * (1.0f + 1e-6f);
    return b;  // normals in every direction
  }
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  glm::dvec3 normal_sum(0.0);
  double area_sum = 0;
  for (size_t i = 0; i < g.indices.size(); ++i) {
    const glm::u32vec3 t = g.indices[i];
    for (const uint32_t v : {t.x, t.y, t.z}) {
      lo = glm::min(lo, glm::dvec3(g.positions[v]));
      hi = glm::max(hi, glm::dvec3(g.positions[v]));
    }
    const double a = double(triangles_.pmf(uint32_t(i)));
    normal_sum += a * glm::dvec3(g.face_normals[i]);
    area_sum += a;
  }
  b.center = glm::vec3(0.5 * (lo + hi));
  // Rounding the centre to float moves it by an ulp: the radius covers that too.
  b.radius = float(0.5 * glm::length(hi - lo)) * (1.0f + 1e-5f) +
             2.0f * gamma_bound(1) * glm::length(glm::abs(b.center));
  const double length = glm::length(normal_sum);
  if (!(length > 1e-3 * area_sum)) return b;  // normals all round: no cone
  const glm::dvec3 w = normal_sum / length;
  double cos_o = 1;
  for (const glm::vec3& n : g.face_normals) cos_o = std::min(cos_o, glm::dot(glm::dvec3(n), w));
  b.w = glm::vec3(w);
  // Slack for the float normals and w.
  b.cos_theta_o = float(std::max(-1.0, cos_o - 1e-5));
  return b;
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
