// Exact spheres as Embree user geometry, intersected in double precision.
#pragma once

#include <embree3/rtcore.h>

#include "render/geometry/geometry.h"

namespace tessera {

/// Attaches the bounds, intersect and occluded callbacks for `sphere` (which must outlive the
/// Embree geometry) to a RTC_GEOMETRY_TYPE_USER geometry with one primitive.
void attach_sphere_callbacks(RTCGeometry geometry, const Geometry* sphere);

/// The parametric distances of o + t d's crossings with the sphere, in double precision
/// (numerically stable form of Haines et al., "Precision Improvements for Ray/Sphere
/// Intersection", Ray Tracing Gems, 2019). Returns false when the ray misses; t0 <= t1.
bool intersect_sphere(const glm::dvec3& center, double radius, const glm::dvec3& o,
                      const glm::dvec3& d, double* t0, double* t1);

}  // namespace tessera
