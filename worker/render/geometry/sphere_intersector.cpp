#include "render/geometry/sphere_intersector.h"

#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

#include "render/math/float_rounding.h"

namespace tessera {

namespace {

// intersect_sphere's body, inlined into the Embree callbacks (called out of line it cost the
// hexroom's callbacks a call and the vectors' round trip through memory per lane).
[[gnu::always_inline]] inline bool sphere_roots(const glm::dvec3& center, double radius, const glm::dvec3& o,
                                                const glm::dvec3& d, double* t0, double* t1) {
  // Haines et al.'s form without normalising d (one division and one square root fewer per
  // ray, and a miss costs one division): with a = |d|^2, b = f.d and l = f - (b / a) d, the
  // discriminant b^2 - a c equals a (r^2 - |l|^2), whose second factor is the squared distance
  // from the centre to the line, computed from the closest point rather than as |f|^2 - b^2 / a,
  // which cancels catastrophically for far-away rays. Then q = -b - sign(b) sqrt(a (r^2 - |l|^2))
  // and the roots are q / a and c / q, each free of cancellation.
  const double a = glm::dot(d, d);
  if (!(a > 0)) return false;
  const double inv_a = 1.0 / a;
  const glm::dvec3 f = o - center;
  const double b = glm::dot(f, d);
  const glm::dvec3 l = f - (b * inv_a) * d;
  const double r2 = radius * radius;
  const double disc = r2 - glm::dot(l, l);
  if (disc < 0) return false;
  const double c = glm::dot(f, f) - r2;
  const double q = -b - std::copysign(std::sqrt(a * disc), b);
  double a0 = q * inv_a, a1 = q == 0 ? 0 : c / q;
  if (a0 > a1) std::swap(a0, a1);
  *t0 = a0;
  *t1 = a1;
  return true;
}

}  // namespace

bool intersect_sphere(const glm::dvec3& center, double radius, const glm::dvec3& o,
                      const glm::dvec3& d, double* t0, double* t1) {
  return sphere_roots(center, radius, o, d, t0, t1);
}

namespace {

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* s = static_cast<const Geometry*>(args->geometryUserPtr);
  // Rounded outward so the float box contains the double sphere.
  const glm::dvec3 lo = s->center - s->radius, hi = s->center + s->radius;
  args->bounds_o->lower_x = round_down(lo.x);
  args->bounds_o->lower_y = round_down(lo.y);
  args->bounds_o->lower_z = round_down(lo.z);
  args->bounds_o->upper_x = round_up(hi.x);
  args->bounds_o->upper_y = round_up(hi.y);
  args->bounds_o->upper_z = round_up(hi.z);
}

/// The nearest crossing of o + t d with t in (tnear, tfar], or NaN.
[[gnu::always_inline]] inline double nearest_crossing(const Geometry* s, const glm::dvec3& o, const glm::dvec3& d,
                                                     float tnear, float tfar) {
  double t0, t1;
  if (!sphere_roots(s->center, s->radius, o, d, &t0, &t1)) return NAN;
  if (t0 > tnear && t0 <= tfar) return t0;
  if (t1 > tnear && t1 <= tfar) return t1;
  return NAN;
}

// Embree calls these with N = 1 for rtcIntersect1 and with N = 4, 8 or 16 for ray packets
// (worker/render/scene/packet_tracer.h), lanes switched off by valid[i] == 0; each lane is solved
// alone, with the same double-precision arithmetic whatever N is. Only the fields the solve
// needs are read (not rtcGetRayFromRayN's whole ray: the callbacks are 6 % of a render of
// the hexroom).
void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* s = static_cast<const Geometry*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i]) continue;
    const glm::dvec3 o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
    const glm::dvec3 d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
    float& tfar = RTCRayN_tfar(rays, N, i);
    const double t = nearest_crossing(s, o, d, RTCRayN_tnear(rays, N, i), tfar);
    if (std::isnan(t)) continue;
    const float tf = float(t);
    if (!(tf <= tfar)) continue;
    tfar = tf;
    // Embree's geometric normal need not be unit length (nothing of the renderer reads it:
    // TraceableScene recomputes the unit normal from the hit point), so no division.
    const glm::vec3 n(o + t * d - s->center);
    RTCHitN_Ng_x(hits, N, i) = n.x;
    RTCHitN_Ng_y(hits, N, i) = n.y;
    RTCHitN_Ng_z(hits, N, i) = n.z;
    RTCHitN_u(hits, N, i) = 0;
    RTCHitN_v(hits, N, i) = 0;
    RTCHitN_primID(hits, N, i) = args->primID;
    RTCHitN_geomID(hits, N, i) = args->geomID;
    RTCHitN_instID(hits, N, i, 0) = args->context->instID[0];
  }
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* s = static_cast<const Geometry*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = args->ray;
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i]) continue;
    const glm::dvec3 o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
    const glm::dvec3 d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
    float& tfar = RTCRayN_tfar(rays, N, i);
    if (!std::isnan(nearest_crossing(s, o, d, RTCRayN_tnear(rays, N, i), tfar))) tfar = -INFINITY;
  }
}

}  // namespace

void attach_sphere_callbacks(RTCGeometry geometry, const Geometry* sphere) {
  rtcSetGeometryUserPrimitiveCount(geometry, 1);
  rtcSetGeometryUserData(geometry, const_cast<Geometry*>(sphere));
  rtcSetGeometryBoundsFunction(geometry, sphere_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geometry, sphere_intersect);
  rtcSetGeometryOccludedFunction(geometry, sphere_occluded);
}

}  // namespace tessera
