// Closed meshes do not leak: a ray from inside aimed exactly at a shared edge or vertex of two
// triangles hits one of them, with single-ray and packet queries, closest-hit and shadow alike.
// A leak lets a camera or bounce ray escape a closed room (a black speck, or environment light
// inside the room) and a shadow ray reach a light through a wall. These rays are the worst
// case for a triangle test that is not watertight: the two triangles' edge functions must
// agree exactly on the shared edge, for every rounding.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "render/scene/embree_packet.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

/// An icosphere of `levels` subdivisions (each triangle split in four, new vertices pushed to
/// the sphere), shared vertices indexed once: every edge belongs to two triangles.
Shape icosphere(glm::dvec3 center, double radius, int levels, uint32_t material) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<glm::u32vec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (glm::dvec3& v : p) v = glm::normalize(v);
  for (int level = 0; level < levels; ++level) {
    std::vector<glm::u32vec3> next;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    const auto middle = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(glm::normalize(p[a] + p[b]));
      return mid[key] = uint32_t(p.size() - 1);
    };
    for (const glm::u32vec3& t3 : f) {
      const uint32_t ab = middle(t3.x, t3.y), bc = middle(t3.y, t3.z), ca = middle(t3.z, t3.x);
      next.insert(next.end(), {{t3.x, ab, ca}, {t3.y, bc, ab}, {t3.z, ca, bc}, {ab, bc, ca}});
    }
    f.swap(next);
  }
  Shape sh;
  sh.kind = Shape::Kind::triangles;
  for (const glm::dvec3& v : p) sh.positions.push_back(center + radius * v);
  sh.indices = f;
  sh.material = material;
  sh.origin = "icosphere";
  return sh;
}

/// Points on every edge of the shape's triangles (both ends included): where a ray from inside
/// is most likely to slip between two triangles.
std::vector<glm::vec3> edge_points(const Shape& sh, int per_edge) {
  std::vector<glm::vec3> out;
  for (const glm::u32vec3& t3 : sh.indices) {
    const uint32_t v[3] = {t3.x, t3.y, t3.z};
    for (int e = 0; e < 3; ++e) {
      const glm::vec3 a(sh.positions[v[e]]), b(sh.positions[v[(e + 1) % 3]]);
      for (int k = 0; k <= per_edge; ++k) out.push_back(a + (b - a) * (float(k) / float(per_edge)));
    }
  }
  return out;
}

struct Leaks {
  int closest = 0;
  int shadow = 0;
  int rays = 0;
};

/// Rays from each of `origins` to each of `targets` (all inside / on the closed shape), traced
/// one at a time and in 16-wide packets; counts the closest-hit rays that find nothing and the
/// shadow rays (to twice the distance: beyond the surface) that are not blocked.
Leaks trace_at_edges(const TraceableScene& scene, const std::vector<glm::vec3>& origins,
                     const std::vector<glm::vec3>& targets) {
  Leaks leaks;
  std::vector<std::pair<glm::vec3, glm::vec3>> rays;
  for (const glm::vec3& o : origins) {
    for (const glm::vec3& t : targets) rays.push_back({o, t - o});
  }
  for (const auto& [o, d] : rays) {
    Hit hit;
    if (!scene.intersect(Ray{o, d}, &hit)) ++leaks.closest;
    if (!scene.occluded(o, d, 2.0f)) ++leaks.shadow;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t first = 0; first < rays.size(); first += 16) {
    alignas(64) RTCRayHit16 rh{};
    alignas(64) RTCRay16 shadow{};
    alignas(64) int valid[16];
    for (int lane = 0; lane < 16; ++lane) {
      const bool on = first + size_t(lane) < rays.size();
      valid[lane] = on ? -1 : 0;
      const auto& [o, d] = rays[on ? first + size_t(lane) : 0];
      for (RTCRay16* r : {&rh.ray, &shadow}) {
        r->org_x[lane] = o.x;
        r->org_y[lane] = o.y;
        r->org_z[lane] = o.z;
        r->dir_x[lane] = d.x;
        r->dir_y[lane] = d.y;
        r->dir_z[lane] = d.z;
        r->tnear[lane] = 0.0f;
        r->mask[lane] = 0xffffffffu;
      }
      rh.ray.tfar[lane] = std::numeric_limits<float>::infinity();
      shadow.tfar[lane] = 2.0f;
      rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
    }
    EmbreePacket<16>::intersect(valid, scene.embree_scene(), &context, &rh);
    EmbreePacket<16>::occluded(valid, scene.embree_scene(), &context, &shadow);
    for (int lane = 0; lane < 16 && first + size_t(lane) < rays.size(); ++lane) {
      if (rh.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) ++leaks.closest;
      if (!(shadow.tfar[lane] < 0.0f)) ++leaks.shadow;
    }
  }
  leaks.rays = int(2 * rays.size());
  return leaks;
}

std::vector<glm::vec3> interior_points(glm::dvec3 center, double extent, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<glm::vec3> out;
  for (int i = 0; i < count; ++i) out.push_back(glm::vec3(center + glm::dvec3(u(rng), u(rng), u(rng))));
  return out;
}

TEST(Watertight, RaysAtTheEdgesOfABoxNeverEscape) {
  for (const double scale : {1e-3, 1.0, 1e3}) {
    Scene s;
    const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
    // Off the origin and not axis-symmetric, so coordinates round differently per vertex.
    const glm::dvec3 lo = glm::dvec3(-1.3, -0.7, -2.1) * scale + glm::dvec3(0.1, 3.7, -1.9) * scale;
    const glm::dvec3 hi = glm::dvec3(1.9, 1.1, 0.6) * scale + glm::dvec3(0.1, 3.7, -1.9) * scale;
    s.shapes.push_back(test::box(lo, hi, m, true));
    const TraceableScene scene(s, 4, 4, "");
    const glm::dvec3 center = (lo + hi) * 0.5;
    const Leaks leaks = trace_at_edges(scene, interior_points(center, 0.5 * scale, 24, 7),
                                       edge_points(s.shapes[0], 64));
    EXPECT_EQ(leaks.closest, 0) << "scale " << scale << ": closest-hit rays escaped, of " << leaks.rays;
    EXPECT_EQ(leaks.shadow, 0) << "scale " << scale << ": shadow rays passed, of " << leaks.rays;
  }
}

TEST(Watertight, RaysAtTheEdgesAndVerticesOfAMeshSphereNeverEscape) {
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  const glm::dvec3 center(0.37, -1.21, 2.9);
  s.shapes.push_back(icosphere(center, 1.7, 3, m));  // 1,280 triangles
  const TraceableScene scene(s, 4, 4, "");
  const Leaks leaks = trace_at_edges(scene, interior_points(center, 0.5, 6, 11), edge_points(s.shapes[0], 4));
  EXPECT_GT(leaks.rays, 100000);
  EXPECT_EQ(leaks.closest, 0) << "closest-hit rays escaped, of " << leaks.rays;
  EXPECT_EQ(leaks.shadow, 0) << "shadow rays passed, of " << leaks.rays;
}

}  // namespace
}  // namespace tessera
