// Curves (Mitsuba's linearcurve and bsplinecurve) as Embree's round curves, and the hit record
// of a curve hit with Mitsuba's normal, uv and tangents.
#pragma once

#include <cstdint>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "render/geometry/geometry.h"
#include "scene/scene.h"

namespace tessera {

struct Hit;

/// Fills the curve part of `g` from `shape` (Shape::Kind::curves) and returns a new Embree
/// geometry of it, not yet committed: RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE or
/// ROUND_BSPLINE_CURVE over `g`'s float control points (x, y, z, radius) and segment indices,
/// as Mitsuba builds them, with filter functions that drop hits on the inside of a tube (a ray
/// leaving a tube passes out of it, as in Mitsuba, whose Embree culls curve back faces).
/// Returns nullptr when Embree cannot allocate the buffers (the device's error says why).
RTCGeometry new_curve_geometry(RTCDevice device, const Shape& shape, Geometry& g);

/// The hit of ray o + t d on segment `primitive` of curve geometry `g` at Embree's curve
/// parameter `v_local` (the hit's u) as Mitsuba's compute_surface_interaction makes it: p the
/// ray's point at t; the normal points out of the tube (for a linear curve from the centre line
/// point at v_local; for a B-spline with Mitsuba's curvature and radius-change correction);
/// when `need_uv`, uv = (angle around the curve / 2 pi from Mitsuba's frame, (v_local +
/// primitive) / segments) and dpdu, dpdv its partial derivatives, as Mitsuba's.
void fill_curve_hit(const Geometry& g, glm::vec3 o, glm::vec3 d, float t, uint32_t primitive,
                    float v_local, bool need_uv, Hit* hit);

}  // namespace tessera
