#include "scene/mitsuba/mitsuba_clip_check.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>

#include "scene/message_text.h"

namespace tessera {
namespace {

/// The points p (camera space) with dot(n, p) + d >= 0; n is unit length.
struct HalfSpace {
  glm::dvec3 n;
  double d;
  double distance(const glm::dvec3& p) const { return glm::dot(n, p) + d; }
};

/// A convex region of camera space, as the half-spaces it is the intersection of, and its
/// corners when it is bounded.
struct Region {
  std::vector<HalfSpace> planes;
  std::vector<glm::dvec3> corners;  ///< empty for the unbounded region beyond far_clip

  /// True when triangle (a, b, c) has a point in the region: the triangle clipped by every
  /// plane in turn (Sutherland-Hodgman) keeps some area or point.
  bool meets_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const {
    std::vector<glm::dvec3> polygon = {a, b, c}, clipped;
    for (const HalfSpace& h : planes) {
      clipped.clear();
      for (size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec3& p = polygon[i];
        const glm::dvec3& q = polygon[(i + 1) % polygon.size()];
        double dp = h.distance(p), dq = h.distance(q);
        if (dp >= 0) clipped.push_back(p);
        if ((dp >= 0) != (dq >= 0)) clipped.push_back(p + (q - p) * (dp / (dp - dq)));
      }
      polygon.swap(clipped);
      if (polygon.empty()) return false;
    }
    return true;
  }

  /// True when the surface of the sphere may cross the region: its distance to the region
  /// (bounded below by its distance to each half-space) is at most r, and, for a bounded
  /// region, the region is not all inside it (some corner is at least r away).
  bool may_meet_sphere(const glm::dvec3& center, double r) const {
    for (const HalfSpace& h : planes) {
      if (h.distance(center) < -r) return false;
    }
    if (corners.empty()) return true;
    return std::any_of(corners.begin(), corners.end(),
                       [&](const glm::dvec3& p) { return glm::length(p - center) >= r; });
  }
};

/// Camera rays at local depth z reach |x| <= offset.x + z * slope.x (and so for y).
struct Cone {
  glm::dvec2 slope;
  /// The aperture radius (a thin lens sees from a disk, not a point); for an orthographic
  /// camera, whose slope is 0, the half extents of its view.
  glm::dvec2 offset;
};

Cone cone_of(const MitsubaSensor& sensor) {
  const Camera& c = sensor.camera;
  if (c.projection == Projection::orthographic) {  // local x in [-1, 1], y in [-1, 1] / aspect
    double aspect = double(sensor.film.width) / double(sensor.film.height);
    return Cone{glm::dvec2(0), glm::dvec2(1, 1 / aspect) * (1 + 1e-9)};
  }
  glm::dvec2 slope =
      fov_half_tangents(c.fov_deg, c.fov_axis, double(sensor.film.width) / double(sensor.film.height));
  // A lens ray runs from a point of the aperture to a point of the focus plane.
  double a = c.aperture_radius;
  if (a > 0) slope += glm::dvec2(a / c.focus_distance);
  return Cone{slope * (1 + 1e-9), glm::dvec2(a)};  // a hair wider: rounding must not hide a clipped point
}

/// The four sides of the cone: |x| <= offset + z slope.x, |y| <= offset + z slope.y.
std::vector<HalfSpace> sides(const Cone& cone) {
  std::vector<HalfSpace> planes;
  for (int axis = 0; axis < 2; ++axis) {
    for (double sign : {1.0, -1.0}) {
      glm::dvec3 n(0);
      n[axis] = -sign;
      n.z = cone.slope[axis];
      double length = glm::length(n);
      planes.push_back(HalfSpace{n / length, cone.offset[axis] / length});
    }
  }
  return planes;
}

Region near_region(const Cone& cone, double near) {
  Region r;
  r.planes = sides(cone);
  r.planes.push_back(HalfSpace{{0, 0, 1}, 0});      // z >= 0
  r.planes.push_back(HalfSpace{{0, 0, -1}, near});  // z <= near
  for (double z : {0.0, near}) {
    glm::dvec2 half = cone.offset + z * cone.slope;
    for (double sx : {-1.0, 1.0}) {
      for (double sy : {-1.0, 1.0}) r.corners.emplace_back(sx * half.x, sy * half.y, z);
    }
  }
  return r;
}

Region far_region(const Cone& cone, double far) {
  Region r;
  r.planes = sides(cone);
  r.planes.push_back(HalfSpace{{0, 0, 1}, -far});  // z >= far
  return r;
}

}  // namespace

void check_mitsuba_clip_planes(const MitsubaSensor& sensor, const std::vector<Shape>& shapes) {
  const glm::dmat4 world_to_camera = glm::inverse(sensor.camera_to_world.matrix());
  auto local = [&](const glm::dvec3& p) { return glm::dvec3(world_to_camera * glm::dvec4(p, 1)); };
  const Cone cone = cone_of(sensor);
  // An orthographic camera's rays start at local z = near_clip, as Tessera's do (its position
  // is there): only the far plane can differ. They end after far_clip - near_clip scene units,
  // at a local depth that the scale along the view axis shrinks.
  const bool orthographic = sensor.camera.projection == Projection::orthographic;
  const double view_scale = glm::length(glm::dvec3(sensor.camera_to_world.matrix()[2]));
  const double far_z = orthographic
                           ? sensor.near_clip + (sensor.far_clip - sensor.near_clip) / view_scale
                           : sensor.far_clip;
  double min_scale = 1;  // rigid for the other cameras
  if (orthographic) {
    min_scale = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      min_scale = std::min(min_scale, glm::length(glm::dvec3(sensor.camera_to_world.matrix()[i])));
    }
  }
  const Region near = near_region(cone, sensor.near_clip);
  const Region far = far_region(cone, far_z);
  auto refuse = [&](const Shape& shape, bool is_near) {
    fail_at(*sensor.element,
            std::string(is_near ? "near_clip " : "far_clip ") +
                format_number(is_near ? sensor.near_clip : sensor.far_clip) +
                " could hide part of " + shape.origin +
                ", and Tessera does not clip: " + (is_near ? "lower near_clip" : "raise far_clip"));
  };
  for (const Shape& shape : shapes) {
    if (shape.kind == Shape::Kind::sphere) {
      glm::dvec3 c = local(shape.center);
      // Camera space is scaled for an orthographic camera: a ball that holds the sphere there.
      const double r = shape.radius / min_scale;
      if (!orthographic && near.may_meet_sphere(c, r)) refuse(shape, true);
      if (far.may_meet_sphere(c, r)) refuse(shape, false);
      continue;
    }
    if (shape.kind == Shape::Kind::sdfgrid) {
      // The surface lies in the grid's box: the ball around its 8 corners.
      glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
      for (int k = 0; k < 8; ++k) {
        const glm::dvec3 p(shape.to_world * glm::dvec4(k & 1, (k >> 1) & 1, k >> 2, 1.0));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      const glm::dvec3 c = local(0.5 * (lo + hi));
      const double r = 0.5 * glm::length(hi - lo) / min_scale;
      if (!orthographic && near.may_meet_sphere(c, r)) refuse(shape, true);
      if (far.may_meet_sphere(c, r)) refuse(shape, false);
      continue;
    }
    if (shape.kind == Shape::Kind::curves) {
      // The tubes lie in the ball around the control points' box, widened by the largest radius.
      glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
      double r_max = 0;
      for (const glm::dvec4& cp : shape.control_points) {
        lo = glm::min(lo, glm::dvec3(cp));
        hi = glm::max(hi, glm::dvec3(cp));
        r_max = std::max(r_max, cp.w);
      }
      const glm::dvec3 c = local(0.5 * (lo + hi));
      const double r = (0.5 * glm::length(hi - lo) + r_max) / min_scale;
      if (!orthographic && near.may_meet_sphere(c, r)) refuse(shape, true);
      if (far.may_meet_sphere(c, r)) refuse(shape, false);
      continue;
    }
    std::vector<glm::dvec3> p;
    p.reserve(shape.positions.size());
    for (const glm::dvec3& q : shape.positions) p.push_back(local(q));
    for (const glm::u32vec3& t : shape.indices) {
      if (!orthographic && near.meets_triangle(p[t.x], p[t.y], p[t.z])) refuse(shape, true);
      if (far.meets_triangle(p[t.x], p[t.y], p[t.z])) refuse(shape, false);
    }
  }
}

}  // namespace tessera
