#include "render/geometry/curve.h"

#include <cmath>
#include <algorithm>
#include <cstring>

#include <glm/geometric.hpp>

#include "render/geometry/hit.h"
#include "render/math/ray_offset.h"
#include "scene/mesh/curve_file.h"

namespace tessera {
namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

/// Embree reports both sides of a round curve; Mitsuba's Embree (and its OptiX) see only the
/// outside. A hit whose geometric normal faces along the ray is on the inside: drop it.
void cull_inside(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float ng_x = RTCHitN_Ng_x(args->hit, args->N, i);
    const float ng_y = RTCHitN_Ng_y(args->hit, args->N, i);
    const float ng_z = RTCHitN_Ng_z(args->hit, args->N, i);
    const float d_x = RTCRayN_dir_x(args->ray, args->N, i);
    const float d_y = RTCRayN_dir_y(args->ray, args->N, i);
    const float d_z = RTCRayN_dir_z(args->ray, args->N, i);
    if (ng_x * d_x + ng_y * d_y + ng_z * d_z > 0) args->valid[i] = 0;
  }
}

/// The error bound of a curve hit o + t d on a tube of radius up to r_max: the rounding of the
/// product and sum, and the error of Embree's t. Embree solves curve hits in float relative to
/// the segment (a quadratic for linear curves, Newton steps for B-splines), with no error bound
/// we could derive; measured instead: with 1/1024 of the radius, rays leaving a tube at scale
/// 1e-3 hit it again (curve_test.cpp, SpawnedRaysDoNotHitTheTubeAgain), with 1/32 none do at
/// scales 1e-3, 1 and 1e3.
glm::vec3 point_error(glm::vec3 o, glm::vec3 td, float r_max) {
  return gamma_bound(3) * (glm::abs(o) + glm::abs(td)) + glm::vec3(0x1p-5f * r_max);
}

/// Mitsuba's local_frame: an axis v_rot in the plane normal to the tangent, leaning to +z
/// (+y where the tangent is +-z), and v_rad = v_rot x tangent. uv's u is the angle from v_rad
/// towards v_rot.
void local_frame(glm::vec3 tangent, glm::vec3* v_rot, glm::vec3* v_rad) {
  const glm::vec3 guide(0, 0, 1);
  *v_rot = std::abs(glm::dot(guide, tangent)) == 1.0f
               ? glm::vec3(0, 1, 0)
               : glm::normalize(guide - tangent * glm::dot(tangent, guide));
  *v_rad = glm::cross(*v_rot, tangent);
}

/// The angle of unit vector `rad` around the curve, as a fraction of a turn in [0, 1).
float angle_fraction(glm::vec3 rad, glm::vec3 v_rot, glm::vec3 v_rad) {
  float u = std::atan2(glm::dot(v_rot, rad), glm::dot(v_rad, rad));
  if (u < 0) u += kTwoPi;
  return u * (1.0f / kTwoPi);
}

/// The centre line, radius and their derivatives of a cubic B-spline segment at v.
struct BsplinePoint {
  glm::vec3 c, dc, ddc, dddc;
  float r, dr;
};

BsplinePoint bspline_point(const glm::vec4* cp, float v) {
  const float v2 = v * v, v3 = v2 * v;
  const float w[4] = {(-v3 + 3 * v2 - 3 * v + 1) / 6, (3 * v3 - 6 * v2 + 4) / 6,
                      (-3 * v3 + 3 * v2 + 3 * v + 1) / 6, v3 / 6};
  const float dw[4] = {(-3 * v2 + 6 * v - 3) / 6, (9 * v2 - 12 * v) / 6,
                       (-9 * v2 + 6 * v + 3) / 6, (3 * v2) / 6};
  const float ddw[4] = {-v + 1, 3 * v - 2, -3 * v + 1, v};
  const float dddw[4] = {-1, 3, -3, 1};
  BsplinePoint b{glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(0), 0, 0};
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 p(cp[i]);
    b.c += w[i] * p;
    b.dc += dw[i] * p;
    b.ddc += ddw[i] * p;
    b.dddc += dddw[i] * p;
    b.r += w[i] * cp[i].w;
    b.dr += dw[i] * cp[i].w;
  }
  return b;
}

/// Mitsuba's coordinate_system(n): the s and t axes of Frame3f(n).
void coordinate_system(glm::vec3 n, glm::vec3* s, glm::vec3* t) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  *s = glm::vec3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  *t = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

/// dp/du and dp/dv of a B-spline tube at angle fraction u (Mitsuba's partials(): Frenet frame,
/// curvature and torsion), v scaled from the segment to the whole shape by `segments`.
void bspline_tangents(const BsplinePoint& b, float u, glm::vec3 v_rot, glm::vec3 v_rad,
                      float segments, Hit* hit) {
  const float norm_dc = glm::length(b.dc);
  const glm::vec3 cross_dc_ddc = glm::cross(b.dc, b.ddc);
  const float norm_cross = glm::length(cross_dc_ddc);
  float kappa = norm_cross / (norm_dc * norm_dc * norm_dc);
  float tau = glm::dot(b.dddc, cross_dc_ddc) / (norm_cross * norm_cross);
  if (norm_cross < 1e-6f || glm::length(b.dddc) < 1e-6f) tau = 0;  // Mitsuba's thresholds
  const glm::vec3 frame_t = b.dc / norm_dc;
  glm::vec3 frame_n = glm::normalize(glm::cross(cross_dc_ddc, b.dc));
  glm::vec3 frame_b = glm::normalize(glm::cross(frame_t, frame_n));
  if (kappa < 5.9604645e-8f) {  // dr::Epsilon<float>: a straight piece has no Frenet frame
    kappa = 0;
    tau = 0;
    coordinate_system(frame_t, &frame_n, &frame_b);
  }
  const glm::vec3 rad = std::cos(u * kTwoPi) * v_rad + std::sin(u * kTwoPi) * v_rot;
  const float cos_theta = glm::dot(frame_n, rad), sin_theta = glm::dot(frame_b, rad);
  const glm::vec3 radu = -sin_theta * frame_n + cos_theta * frame_b;
  const glm::vec3 radv = norm_dc * cos_theta * (-kappa * frame_t + tau * frame_b) +
                         norm_dc * sin_theta * (-tau * frame_n);
  hit->dpdu = (b.r * radu) * kTwoPi;
  hit->dpdv = (b.dc + b.dr * rad + b.r * radv) * segments;
}

}  // namespace

RTCGeometry new_curve_geometry(RTCDevice device, const Shape& shape, Geometry& g) {
  g.kind = Geometry::Kind::curves;
  g.bspline = shape.curve_basis == CurveBasis::bspline;
  g.control_points.reserve(shape.control_points.size());
  for (const glm::dvec4& cp : shape.control_points) g.control_points.emplace_back(cp);
  // Mitsuba's segment indices: each curve of n points has n - 1 (linear) or n - 3 (B-spline)
  // segments, starting at its points in order.
  uint32_t first = 0;
  for (uint32_t n : shape.curve_sizes) {
    const uint32_t segments = curve_segment_count(shape.curve_basis, n);
    for (uint32_t j = 0; j < segments; ++j) g.segments.push_back(first + j);
    first += n;
  }
  g.material = shape.material;

  RTCGeometry geom = rtcNewGeometry(device, g.bspline ? RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE
                                                      : RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
  if (!geom) return nullptr;
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                RTC_FORMAT_FLOAT4, 4 * sizeof(float),
                                                                g.control_points.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(uint32_t), g.segments.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geom);
    return nullptr;
  }
  std::memcpy(vertices, g.control_points.data(), g.control_points.size() * 4 * sizeof(float));
  std::memcpy(indices, g.segments.data(), g.segments.size() * sizeof(uint32_t));
  rtcSetGeometryIntersectFilterFunction(geom, cull_inside);
  rtcSetGeometryOccludedFilterFunction(geom, cull_inside);
  return geom;
}

void fill_curve_hit(const Geometry& g, glm::vec3 o, glm::vec3 d, float t, uint32_t primitive,
                    float v_local, bool need_uv, Hit* hit) {
  const glm::vec4* cp = &g.control_points[g.segments[primitive]];
  const glm::vec3 p = o + t * d;
  hit->sp.p = p;
  const float segments = float(g.segments.size());
  const float v = (v_local + float(primitive)) / segments;
  if (!g.bspline) {
    const glm::vec3 p0(cp[0]), p1(cp[1]);
    const glm::vec3 c = p0 * (1.0f - v_local) + p1 * v_local;
    const glm::vec3 n = glm::normalize(p - c);
    hit->sp.ng = n;
    hit->ns = n;
    hit->sp.p_error = point_error(o, t * d, std::max(cp[0].w, cp[1].w));
    if (!need_uv) return;
    const glm::vec3 axis = glm::normalize(p1 - p0);
    glm::vec3 v_rot, v_rad;
    local_frame(axis, &v_rot, &v_rad);
    hit->uv = {angle_fraction(n, v_rot, v_rad), v};
    hit->dpdu = kTwoPi * glm::cross(axis, p - c);
    hit->dpdv = segments * ((p1 - p0) + (cp[1].w - cp[0].w) * n);
    return;
  }
  const BsplinePoint b = bspline_point(cp, v_local);
  const glm::vec3 rad_vec = p - b.c;
  // Mitsuba's normal of the swept tube: the radial vector corrected for the centre line's
  // curvature and the radius' change along it.
  const glm::vec3 n = glm::normalize((glm::dot(b.dc, b.dc) - glm::dot(rad_vec, b.ddc)) * rad_vec -
                                     (b.dr * b.r) * b.dc);
  hit->sp.ng = n;
  hit->ns = n;
  hit->sp.p_error =
      point_error(o, t * d, std::max(std::max(cp[0].w, cp[1].w), std::max(cp[2].w, cp[3].w)));
  if (!need_uv) return;
  glm::vec3 v_rot, v_rad;
  local_frame(glm::normalize(b.dc), &v_rot, &v_rad);
  const float u = angle_fraction(glm::normalize(rad_vec), v_rot, v_rad);
  hit->uv = {u, v};
  bspline_tangents(b, u, v_rot, v_rad, segments, hit);
}

}  // namespace tessera
