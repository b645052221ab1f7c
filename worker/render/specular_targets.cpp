#include "specular_targets.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <glm/mat3x3.hpp>
#include <string>

#include "geometry.h"
#include "material.h"

namespace tessera {

bool purely_specular(const RenderMaterial& m, const std::vector<RenderMaterial>& materials) {
  const bool delta = m.type == MaterialType::mirror || m.type == MaterialType::conductor ||
                     m.type == MaterialType::glass || m.type == MaterialType::thin_glass;
  if (!delta) return false;
  if (m.back >= 0 && size_t(m.back) < materials.size()) {
    const RenderMaterial& back = materials[size_t(m.back)];
    if (back.back >= 0) return false;  // no deeper nesting: keep the test finite
    return purely_specular(back, materials);
  }
  return true;
}

SpecularTarget bounding_sphere(const std::vector<glm::vec3>& points) {
  if (points.empty()) return {};
  // The box's sphere: an upper bound, and sometimes the tighter one (a cube's corners).
  glm::vec3 lo = points[0], hi = points[0];
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 box_center = 0.5f * (lo + hi);
  float box_r2 = 0;
  for (const glm::vec3& p : points) {
    const glm::vec3 d = p - box_center;
    box_r2 = std::max(box_r2, glm::dot(d, d));
  }
  // Ritter (1990): the farthest pair among the extremes along each axis as a first diameter,
  // then grow the sphere just enough to take in each point outside it.
  size_t min_i[3] = {0, 0, 0}, max_i[3] = {0, 0, 0};
  for (size_t i = 0; i < points.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      if (points[i][a] < points[min_i[a]][a]) min_i[a] = i;
      if (points[i][a] > points[max_i[a]][a]) max_i[a] = i;
    }
  }
  int axis = 0;
  float best = -1;
  for (int a = 0; a < 3; ++a) {
    const glm::vec3 d = points[max_i[a]] - points[min_i[a]];
    if (glm::dot(d, d) > best) {
      best = glm::dot(d, d);
      axis = a;
    }
  }
  glm::dvec3 c = 0.5 * (glm::dvec3(points[min_i[axis]]) + glm::dvec3(points[max_i[axis]]));
  double r = 0.5 * std::sqrt(double(best));
  for (const glm::vec3& p : points) {
    const glm::dvec3 d = glm::dvec3(p) - c;
    const double dist = glm::length(d);
    if (dist > r) {
      const double new_r = 0.5 * (r + dist);
      c += d * ((new_r - r) / dist);
      r = new_r;
    }
  }
  // Rounding to float must not leave a point outside: take the float sphere's farthest point.
  const glm::vec3 cf(c);
  float ritter_r2 = 0;
  for (const glm::vec3& p : points) {
    const glm::vec3 d = p - cf;
    ritter_r2 = std::max(ritter_r2, glm::dot(d, d));
  }
  const bool ritter = ritter_r2 < box_r2;
  const glm::vec3 center = ritter ? cf : box_center;
  // One ulp up, so that every point lies inside whatever the square root rounded to.
  const float radius = std::nextafter(std::sqrt(ritter ? ritter_r2 : box_r2), INFINITY);
  return {center, radius};
}

namespace {

/// The world-space bounding sphere of a shape, or radius 0 when its kind has none here.
SpecularTarget shape_sphere(const Geometry& g, const glm::mat4* to_world) {
  if (g.kind == Geometry::Kind::sphere) {
    if (!to_world) return {glm::vec3(g.center), std::nextafter(float(g.radius), INFINITY)};
    // Under a transform: the centre mapped, the radius scaled by the longest axis.
    const glm::mat3 m(*to_world);
    const float scale = std::max({glm::length(m[0]), glm::length(m[1]), glm::length(m[2])});
    const glm::vec3 c(*to_world * glm::vec4(glm::vec3(g.center), 1.0f));
    return {c, std::nextafter(float(g.radius) * scale * (1.0f + 1e-6f), INFINITY)};
  }
  if (g.kind != Geometry::Kind::triangles || g.positions.empty()) return {};
  if (!to_world) return bounding_sphere(g.positions);
  std::vector<glm::vec3> world;
  world.reserve(g.positions.size());
  for (const glm::vec3& p : g.positions) world.emplace_back(*to_world * glm::vec4(p, 1.0f));
  return bounding_sphere(world);
}

/// How many SpecularTargets::DisabledForTest are alive.
std::atomic<int> disabled_for_test{0};

}  // namespace

SpecularTargets::DisabledForTest::DisabledForTest() { disabled_for_test.fetch_add(1); }
SpecularTargets::DisabledForTest::~DisabledForTest() { disabled_for_test.fetch_sub(1); }

SpecularTargets::SpecularTargets(const std::vector<ShapeRef>& shapes, const std::vector<RenderMaterial>& materials,
                                 float scene_radius) {
  if (disabled_for_test.load(std::memory_order_relaxed) > 0) return;
  std::vector<SpecularTarget> targets;
  for (const ShapeRef& s : shapes) {
    const Geometry& g = *s.geometry;
    if (g.material >= materials.size() || !purely_specular(materials[g.material], materials)) continue;
    const SpecularTarget t = shape_sphere(g, s.to_world);
    if (!(t.radius > 0) || !std::isfinite(t.radius)) continue;
    if (scene_radius > 0 && t.radius > kMaxSceneFraction * scene_radius) continue;
    targets.push_back(t);
  }
  if (targets.size() > size_t(kMaxTargets)) {
    // The largest spheres are kept: they subtend the largest cones from most of the scene.
    std::stable_sort(targets.begin(), targets.end(),
                     [](const SpecularTarget& a, const SpecularTarget& b) { return a.radius > b.radius; });
    targets.resize(size_t(kMaxTargets));
  }
  count_ = int(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) {
    lanes_.cx[i] = targets[i].center.x;
    lanes_.cy[i] = targets[i].center.y;
    lanes_.cz[i] = targets[i].center.z;
    lanes_.r[i] = targets[i].radius;
    lanes_.r2[i] = targets[i].radius * targets[i].radius;
  }
}

SpecularTargets::Lanes SpecularTargets::empty_lanes() {
  Lanes l;
  for (int i = 0; i < kMaxTargets; ++i) {
    l.cx[i] = l.cy[i] = l.cz[i] = l.r[i] = 0.0f;
    l.r2[i] = std::numeric_limits<float>::infinity();
  }
  return l;
}

}  // namespace tessera
