// Scenes built in code for the renderer's tests (no parser involved).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/scene.h"

namespace tessera::test {

inline uint32_t add_diffuse(Scene& s, glm::dvec3 albedo, bool two_sided = false) {
  Material m;
  m.name = "m" + std::to_string(s.materials.size());
  m.type = MaterialType::diffuse;
  m.reflectance.value = albedo;
  m.two_sided = two_sided;
  s.materials.push_back(m);
  return uint32_t(s.materials.size() - 1);
}

inline uint32_t add_material(Scene& s, MaterialType type, double ior = 1.5) {
  Material m;
  m.name = "m" + std::to_string(s.materials.size());
  m.type = type;
  m.ior = ior;
  s.materials.push_back(m);
  return uint32_t(s.materials.size() - 1);
}

/// A quad v0..v3, counter-clockwise seen from the front.
inline Shape quad(glm::dvec3 v0, glm::dvec3 v1, glm::dvec3 v2, glm::dvec3 v3, uint32_t material) {
  Shape sh;
  sh.kind = Shape::Kind::triangles;
  sh.positions = {v0, v1, v2, v3};
  sh.indices = {{0, 1, 2}, {0, 2, 3}};
  sh.material = material;
  sh.origin = "quad";
  return sh;
}

inline Shape sphere(glm::dvec3 center, double radius, uint32_t material, bool inward = false) {
  Shape sh;
  sh.kind = Shape::Kind::sphere;
  sh.center = center;
  sh.radius = radius;
  sh.flip_normals = inward;
  sh.material = material;
  sh.origin = "sphere";
  return sh;
}

/// An axis-aligned box [lo, hi], faces outward, or inward when `inward`.
inline Shape box(glm::dvec3 lo, glm::dvec3 hi, uint32_t material, bool inward) {
  Shape sh;
  sh.kind = Shape::Kind::triangles;
  for (int i = 0; i < 8; ++i) {
    sh.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  }
  // Outward counter-clockwise faces.
  const std::vector<glm::u32vec3> faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                           {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                           {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (glm::u32vec3 f : faces) sh.indices.push_back(inward ? glm::u32vec3(f.x, f.z, f.y) : f);
  sh.material = material;
  sh.origin = "box";
  return sh;
}

/// A curves shape of one or more strands (`sizes`: control points per strand; empty = one).
inline Shape curve(CurveBasis basis, std::vector<glm::dvec4> points, uint32_t material,
                   std::vector<uint32_t> sizes = {}) {
  Shape s;
  s.kind = Shape::Kind::curves;
  s.curve_basis = basis;
  s.curve_sizes = sizes.empty() ? std::vector<uint32_t>{uint32_t(points.size())} : sizes;
  s.control_points = std::move(points);
  s.material = material;
  s.origin = "test curve";
  return s;
}

/// Scales every length of the scene by `k` (geometry and camera), keeping the image the same.
inline void scale_scene(Scene& s, double k) {
  s.camera.position *= k;
  s.camera.look_at *= k;
  s.camera.focus_distance *= k;
  s.camera.aperture_radius *= k;
  for (Shape& sh : s.shapes) {
    for (glm::dvec3& p : sh.positions) p *= k;
    sh.center *= k;
    sh.radius *= k;
  }
}

/// A copy of `s` with every length scaled by `k` (scale_scene).
inline Scene scaled(Scene s, double k) {
  scale_scene(s, k);
  return s;
}

/// A small room with every material kind of these helpers and both shape kinds: diffuse walls,
/// a quad light, a glass sphere, a mirror sphere and a two-sided diffuse quad (the determinism
/// and wavefront tests' scene).
inline Scene mixed_room() {
  Scene s;
  const uint32_t white = add_diffuse(s, {0.7, 0.7, 0.7});
  const uint32_t red = add_diffuse(s, {0.7, 0.1, 0.1}, /*two_sided=*/true);
  const uint32_t glass = add_material(s, MaterialType::glass, 1.5);
  const uint32_t mirror = add_material(s, MaterialType::mirror);
  s.shapes.push_back(box({-1, -1, -1}, {1, 1, 1}, white, /*inward=*/true));
  Shape light = quad({-0.3, 0.99, -0.3}, {0.3, 0.99, -0.3}, {0.3, 0.99, 0.3}, {-0.3, 0.99, 0.3}, white);
  light.emission = {10, 9, 8};
  s.shapes.push_back(light);
  s.shapes.push_back(sphere({-0.4, -0.6, 0.0}, 0.35, glass));
  s.shapes.push_back(sphere({0.45, -0.65, -0.3}, 0.3, mirror));
  s.shapes.push_back(quad({-0.9, -0.2, -0.9}, {-0.5, -0.2, -0.9}, {-0.5, 0.3, -0.6}, {-0.9, 0.3, -0.6}, red));
  s.camera.position = {0, 0, 0.95};
  s.camera.look_at = {0, -0.2, 0};
  s.camera.fov_deg = 80;
  return s;
}

}  // namespace tessera::test
