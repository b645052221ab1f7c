#include "sphere_intersector.h"

#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace tessera {

bool intersect_sphere(const glm::dvec3& center, double radius, const glm::dvec3& o,
                      const glm::dvec3& d, double* t0, double* t1) {
  const double len = glm::length(d);
  if (!(len > 0)) return false;
  const glm::dvec3 dh = d / len;
  const glm::dvec3 f = o - center;
  const double b = glm::dot(f, dh);
  // The squared distance from the centre to the line, computed from the closest point rather
  // than as |f|^2 - b^2, which cancels catastrophically for far-away rays.
  const glm::dvec3 l = f - b * dh;
  const double disc = radius * radius - glm::dot(l, l);
  if (disc < 0) return false;
  const double c = glm::dot(f, f) - radius * radius;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  double a0 = q, a1 = q == 0 ? 0 : c / q;
  if (a0 > a1) std::swap(a0, a1);
  *t0 = a0 / len;
  *t1 = a1 / len;
  return true;
}

namespace {

float round_down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}

float round_up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

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

/// The nearest crossing in (tnear, tfar], or NaN.
double nearest_crossing(const Geometry* s, const RTCRay& ray) {
  double t0, t1;
  if (!intersect_sphere(s->center, s->radius, {ray.org_x, ray.org_y, ray.org_z},
                        {ray.dir_x, ray.dir_y, ray.dir_z}, &t0, &t1)) {
    return NAN;
  }
  if (t0 > ray.tnear && t0 <= ray.tfar) return t0;
  if (t1 > ray.tnear && t1 <= ray.tfar) return t1;
  return NAN;
}

// Embree calls these with N = 1 for rtcIntersect1 and with N = 4, 8 or 16 for ray packets
// (worker/render/packet_tracer.h), lanes switched off by valid[i] == 0; each lane is solved
// alone, with the same double-precision arithmetic whatever N is.
void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* s = static_cast<const Geometry*>(args->geometryUserPtr);
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    const RTCRay ray = rtcGetRayFromRayN(rays, args->N, i);
    const double t = nearest_crossing(s, ray);
    if (std::isnan(t)) continue;
    const float tf = float(t);
    if (!(tf <= ray.tfar)) continue;
    RTCRayN_tfar(rays, args->N, i) = tf;
    const glm::dvec3 p = glm::dvec3(ray.org_x, ray.org_y, ray.org_z) +
                         t * glm::dvec3(ray.dir_x, ray.dir_y, ray.dir_z);
    const glm::dvec3 n = (p - s->center) / s->radius;
    RTCHitN_Ng_x(hits, args->N, i) = float(n.x);
    RTCHitN_Ng_y(hits, args->N, i) = float(n.y);
    RTCHitN_Ng_z(hits, args->N, i) = float(n.z);
    RTCHitN_u(hits, args->N, i) = 0;
    RTCHitN_v(hits, args->N, i) = 0;
    RTCHitN_primID(hits, args->N, i) = args->primID;
    RTCHitN_geomID(hits, args->N, i) = args->geomID;
    RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
  }
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* s = static_cast<const Geometry*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    if (!std::isnan(nearest_crossing(s, rtcGetRayFromRayN(args->ray, args->N, i)))) {
      RTCRayN_tfar(args->ray, args->N, i) = -INFINITY;
    }
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
