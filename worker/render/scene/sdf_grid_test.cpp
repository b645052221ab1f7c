// SDF grids (geometry/sdf_grid.h) through TraceableScene: hits land on the trilinear surface of
// a sampled sphere distance and agree with a brute-force march along the ray (so the bricks'
// bounds cut nothing off), rays along cell faces and edges do not leak through, rays spawned
// from hits never hit the surface they leave, extremes of values and scales stay finite, an
// instanced grid hits where a placed one does, and the torus of Mitsuba's docs hits where
// Mitsuba 3.9.1 finds it with its normals (mitsuba_sdfgrid_rays.py).
#include "render/geometry/sdf_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "render/math/ray_offset.h"
#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"
#include "scene/volume_grid_file.h"
#include "scene/native/sdfgrid_shape.h"

namespace tessera {
namespace {

constexpr glm::dvec3 kCentre{0.5, 0.5, 0.5};
constexpr double kRadius = 0.35;

/// The distance to a sphere of radius kRadius around kCentre, sampled at n^3 points of [0, 1]^3
/// and multiplied by `k`.
Shape sphere_grid(uint32_t n, uint32_t material, double k = 1.0, SdfNormals normals = SdfNormals::analytic) {
  Shape s;
  s.kind = Shape::Kind::sdfgrid;
  s.origin = "sphere grid";
  s.sdf_resolution = {n, n, n};
  s.sdf_normals = normals;
  s.material = material;
  for (uint32_t z = 0; z < n; ++z) {
    for (uint32_t y = 0; y < n; ++y) {
      for (uint32_t x = 0; x < n; ++x) {
        const glm::dvec3 p = glm::dvec3(x, y, z) / double(n - 1);
        s.sdf_values.push_back(float(k * (glm::length(p - kCentre) - kRadius)));
      }
    }
  }
  return s;
}

/// The trilinear interpolant of `s` at object-space point p (clamped into the grid), and its
/// object-space gradient: the reference the renderer's answers are checked against.
double interpolant(const Shape& s, glm::dvec3 p, glm::dvec3* gradient = nullptr) {
  const glm::u32vec3 n = s.sdf_resolution;
  glm::dvec3 g = glm::clamp(p, 0.0, 1.0) * (glm::dvec3(n) - 1.0);
  glm::u32vec3 c;
  glm::dvec3 w;
  for (int a = 0; a < 3; ++a) {
    c[a] = std::min(uint32_t(g[a]), n[a] - 2);
    w[a] = g[a] - c[a];
  }
  auto v = [&](uint32_t i) {
    return double(s.sdf_values[(size_t(c.z + (i >> 2)) * n.y + c.y + ((i >> 1) & 1)) * n.x + c.x + (i & 1)]);
  };
  double f = 0;
  glm::dvec3 grad(0.0);
  for (uint32_t i = 0; i < 8; ++i) {
    const glm::dvec3 b(i & 1, (i >> 1) & 1, i >> 2);
    const glm::dvec3 wt = b * w + (1.0 - b) * (1.0 - w);
    f += v(i) * wt.x * wt.y * wt.z;
    const glm::dvec3 sign = 2.0 * b - 1.0;
    grad += v(i) * sign * glm::dvec3(wt.y * wt.z, wt.x * wt.z, wt.x * wt.y);
  }
  if (gradient) *gradient = grad * (glm::dvec3(n) - 1.0);
  return f;
}

/// The first crossing of o + t d (object space, |d| = 1) with the interpolant's zero set, by
/// marching in steps of 1e-3 voxel and bisecting; -1 when none.
double march(const Shape& s, glm::dvec3 o, glm::dvec3 d) {
  const double step = 1e-3 / (s.sdf_resolution.x - 1);
  double t_prev = 0, f_prev = interpolant(s, o);
  for (double t = step; t < 4; t += step) {
    const glm::dvec3 p = o + t * d;
    if (glm::any(glm::lessThan(p, glm::dvec3(0.0))) || glm::any(glm::greaterThan(p, glm::dvec3(1.0)))) {
      if (t > 2) break;
      t_prev = t;
      f_prev = interpolant(s, p);
      continue;
    }
    const double f = interpolant(s, p);
    if ((f <= 0) != (f_prev <= 0)) {
      double lo = t_prev, hi = t;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((interpolant(s, o + mid * d) <= 0) == (f_prev <= 0) ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    t_prev = t;
    f_prev = f;
  }
  return -1;
}

Scene scene_of(const Shape& grid) {
  Scene s;
  test::add_diffuse(s, {0.5, 0.5, 0.5});
  s.shapes.push_back(grid);
  return s;
}

TEST(SdfGrid, HitsLieOnTheSurfaceAndMatchABruteForceMarch) {
  Scene s = scene_of(sphere_grid(9, 0));
  const Shape& grid = s.shapes[0];
  const TraceableScene scene(s, 4, 4, "");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    // From a sphere of radius 1.5 around the grid towards a point near the surface.
    const glm::dvec3 o = kCentre + 1.5 * glm::dvec3(square_to_uniform_sphere({float(u(rng)), float(u(rng))}));
    const glm::dvec3 target = kCentre + 0.45 * (glm::dvec3(u(rng), u(rng), u(rng)) * 2.0 - 1.0);
    const glm::dvec3 d = glm::normalize(target - o);
    const glm::vec3 of(o), df(d);
    Hit hit;
    const bool found = scene.intersect(Ray{of, df}, &hit);
    const double expected = march(grid, glm::dvec3(of), glm::dvec3(df));
    ASSERT_EQ(found, expected >= 0) << "ray " << i << " expected t " << expected;
    if (!found) continue;
    ++hits;
    const double t = glm::dot(glm::dvec3(hit.sp.p) - glm::dvec3(of), glm::dvec3(df));
    EXPECT_NEAR(t, expected, 1e-5) << "ray " << i;
    glm::dvec3 g;
    EXPECT_NEAR(interpolant(grid, glm::dvec3(hit.sp.p), &g), 0.0, 1e-6) << "ray " << i;
    const glm::dvec3 n = glm::normalize(g);
    EXPECT_GT(glm::dot(glm::dvec3(hit.sp.ng), n), 1 - 1e-5) << "ray " << i;
    EXPECT_EQ(hit.ns, hit.sp.ng);  // analytic normals
    EXPECT_EQ(hit.uv, glm::vec2(0.0f));
  }
  EXPECT_GT(hits, 150);
}

TEST(SdfGrid, RaysAlongCellFacesAndEdgesDoNotLeak) {
  const uint32_t n = 9;
  Scene s = scene_of(sphere_grid(n, 0));
  const Shape& grid = s.shapes[0];
  const TraceableScene scene(s, 4, 4, "");
  int checked = 0;
  // Rays parallel to z in the planes x = i / 8 (cell faces), through y = j / 8 (cell edges)
  // and between, and diagonal rays through grid vertices.
  for (uint32_t i = 0; i < n; ++i) {
    for (uint32_t j = 0; j < 4 * n; ++j) {
      const double x = double(i) / (n - 1), y = double(j) / (4 * (n - 1));
      for (const glm::dvec3 d : {glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 1) / std::sqrt(2.0)}) {
        const glm::vec3 o(glm::dvec3(x, y, -1.0) - (d.y > 0 ? glm::dvec3(0, 1, 0) : glm::dvec3(0.0)));
        Hit hit;
        const bool found = scene.intersect(Ray{o, glm::vec3(d)}, &hit);
        const double expected = march(grid, glm::dvec3(o), glm::dvec3(glm::vec3(d)));
        EXPECT_EQ(found, expected >= 0) << "x " << x << " y " << y << " d.y " << d.y;
        if (found && expected >= 0) {
          EXPECT_NEAR(glm::length(glm::dvec3(hit.sp.p) - glm::dvec3(o)), expected, 1e-5);
        }
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, int(2 * n * 4 * n));
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(SdfGrid, SpawnedRaysNeverHitTheSurfaceTheyLeave) {
  for (double scale : {1e-4, 1.0, 1e4}) {
    Shape grid = sphere_grid(12, 0);
    grid.to_world = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(3 * scale, -scale, 50 * scale)),
                               glm::dvec3(scale));
    const TraceableScene scene(scene_of(grid), 4, 4, "");
    const glm::dvec3 centre(grid.to_world * glm::dvec4(kCentre, 1.0));
    const double voxel = scale / 11, kSelfHit = 1e-3;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int outward = 0, inward = 0;
    for (int i = 0; i < 300; ++i) {
      const glm::dvec3 o = centre + 2.0 * scale * glm::dvec3(square_to_uniform_sphere({u(rng), u(rng)}));
      const glm::vec3 d(glm::normalize(centre + 0.2 * scale * glm::dvec3(square_to_uniform_sphere({u(rng), u(rng)})) - o));
      Hit hit;
      if (!scene.intersect(Ray{glm::vec3(o), d}, &hit)) continue;
      ASSERT_TRUE(finite(hit.sp.p) && finite(hit.sp.p_error) && finite(hit.sp.ng) && finite(hit.ns))
          << "scale " << scale << " ray " << i;
      for (int k = 0; k < 30; ++k) {
        const glm::vec3 w = square_to_uniform_sphere({u(rng), u(rng)});
        Hit again;
        const bool found = scene.intersect(Ray{offset_ray_origin(hit.sp, w), w}, &again);
        if (glm::dot(w, hit.sp.ng) > 0) {
          // Leaving the ball. The interpolant's surface has creases at voxel faces, so a
          // grazing ray may meet it again a few hundredths of a voxel away; a self-hit would
          // be within the point's error (1e-7 of its size), far below 1e-3 voxel.
          if (found) {
            EXPECT_GT(glm::length(glm::dvec3(again.sp.p) - glm::dvec3(hit.sp.p)), kSelfHit * voxel)
                << "scale " << scale << " ray " << i;
          }
          ++outward;
        } else {
          // Into the ball: out again (at a crease nearby, or the far side), never at the
          // point left.
          EXPECT_TRUE(found) << "scale " << scale << " ray " << i;
          if (found) {
            EXPECT_GT(glm::length(glm::dvec3(again.sp.p) - glm::dvec3(hit.sp.p)), kSelfHit * voxel)
                << "scale " << scale << " ray " << i;
          }
          ++inward;
        }
      }
    }
    EXPECT_GT(outward, 2000) << scale;
    EXPECT_GT(inward, 2000) << scale;
  }
}

TEST(SdfGrid, ExtremesStayFinite) {
  std::vector<Shape> grids;
  Shape tiny = sphere_grid(2, 0);  // 2 x 2 x 2: one voxel, its corners all outside but one
  tiny.sdf_values = {1, 1, 1, 1, 1, 1, 1, -1};
  grids.push_back(tiny);
  grids.push_back(sphere_grid(7, 0, 1e30, SdfNormals::smooth));
  grids.push_back(sphere_grid(7, 0, 1e-30, SdfNormals::smooth));
  grids.push_back(sphere_grid(7, 0, 1.0, SdfNormals::smooth));
  for (const Shape& g : grids) {
    const TraceableScene scene(scene_of(g), 4, 4, "");
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 500; ++i) {
      const glm::vec3 o = glm::vec3(kCentre) + 2.0f * square_to_uniform_sphere({u(rng), u(rng)});
      const glm::vec3 target(u(rng), u(rng), u(rng));
      Hit hit;
      if (!scene.intersect(Ray{o, target - o}, &hit)) continue;
      ++hits;
      ASSERT_TRUE(finite(hit.sp.p) && finite(hit.sp.p_error) && finite(hit.sp.ng) && finite(hit.ns));
      EXPECT_NEAR(glm::length(hit.sp.ng), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::length(hit.ns), 1.0f, 1e-5f);
      EXPECT_GE(glm::dot(hit.ns, hit.sp.ng), 0.0f);
    }
    EXPECT_GT(hits, 10);
  }
  // Values scaled by 1e30 or 1e-30 leave the surface where it was.
  const Shape a = sphere_grid(7, 0), b = sphere_grid(7, 0, 1e30), c = sphere_grid(7, 0, 1e-30);
  const TraceableScene sa(scene_of(a), 4, 4, ""), sb(scene_of(b), 4, 4, ""), sc(scene_of(c), 4, 4, "");
  const Ray ray{glm::vec3(0.2f, 0.45f, -1.0f), glm::normalize(glm::vec3(0.1f, 0.05f, 1.0f))};
  Hit ha, hb, hc;
  ASSERT_TRUE(sa.intersect(ray, &ha) && sb.intersect(ray, &hb) && sc.intersect(ray, &hc));
  EXPECT_NEAR(glm::length(ha.sp.p - hb.sp.p), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(ha.sp.p - hc.sp.p), 0.0f, 1e-6f);
}

TEST(SdfGrid, InstancedGridHitsWhereAPlacedOneDoes) {
  const glm::dmat4 place = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)), 0.7,
                                       glm::dvec3(0.3, 1, 0.2));
  const glm::dmat4 own = glm::scale(glm::dmat4(1.0), glm::dvec3(2, 1, 1.5));
  Shape placed = sphere_grid(9, 0, 1.0, SdfNormals::smooth);
  placed.to_world = place * own;
  Scene direct = scene_of(placed);
  Scene grouped;
  test::add_diffuse(grouped, {0.5, 0.5, 0.5});
  Shape member = sphere_grid(9, 0, 1.0, SdfNormals::smooth);
  member.to_world = own;
  grouped.groups.push_back({"g", "group", {member}});
  Shape instance;
  instance.kind = Shape::Kind::instance;
  instance.group = 0;
  instance.to_world = place;
  grouped.shapes.push_back(instance);
  const TraceableScene a(direct, 4, 4, ""), b(grouped, 4, 4, "");
  const glm::vec3 centre(place * own * glm::dvec4(kCentre, 1.0));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 o = centre + 4.0f * square_to_uniform_sphere({u(rng), u(rng)});
    const glm::vec3 d = glm::normalize(centre + 0.5f * square_to_uniform_sphere({u(rng), u(rng)}) - o);
    Hit ha, hb;
    const bool fa = a.intersect(Ray{o, d}, &ha), fb = b.intersect(Ray{o, d}, &hb);
    ASSERT_EQ(fa, fb) << "ray " << i;
    if (!fa) continue;
    ++hits;
    EXPECT_LT(glm::length(ha.sp.p - hb.sp.p), 1e-4f) << "ray " << i;
    EXPECT_GT(glm::dot(ha.sp.ng, hb.sp.ng), 1 - 1e-4f) << "ray " << i;
    EXPECT_GT(glm::dot(ha.ns, hb.ns), 1 - 1e-4f) << "ray " << i;
  }
  EXPECT_GT(hits, 200);
}

struct MitsubaRay {
  glm::dvec3 o, d;
  double t;
  glm::dvec3 ng, ns_smooth, ns_analytic;
};

// worker/render/geometry/mitsuba_sdfgrid_rays.py (Mitsuba 3.9.1, scalar_rgb).
const MitsubaRay kMitsubaRays[] = {
    {{0.5, 0.5, -1}, {0, 0, 1}, 1.15591788, {-0.035757184, -0.127241388, -0.991226912}, {-0.035643667, -0.126837432, -0.991283}, {-0.035757184, -0.127241388, -0.991226912}},
    {{0.31, 0.52, -1}, {0, 0, 1}, 1.21788144, {-0.547730625, 0.127222568, -0.826925457}, {-0.564575434, 0.070843704, -0.822335541}, {-0.547730625, 0.127222568, -0.826925457}},
    {{-1, 0.45, 0.52}, {1, 0, 0}, 1.17637002, {-0.7952829, -0.605538785, 0.0291192196}, {-0.78546387, -0.618675232, 0.0169516485}, {-0.7952829, -0.605538785, 0.0291192196}},
    {{0.5, -1, 0.5}, {0, 1, 0}, INFINITY, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
    {{-0.5, -0.4, -0.3}, {1, 0.9, 0.85}, INFINITY, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
    {{1.6, 1.3, 1.5}, {-1, -0.75, -1.1}, 1.0281682, {-0.401189029, 0.127803698, 0.907035649}, {-0.373687834, 0.156818166, 0.914202094}, {-0.401189029, 0.127803698, 0.907035649}},
};

TEST(SdfGrid, TorusHitsMatchMitsuba) {
  const std::string path = std::string(TESSERA_SOURCE_DIR) + "/tests/data/mitsuba/sdfgrid/torus_sdfgrid.vol";
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << path;
  std::stringstream bytes;
  bytes << in.rdbuf();
  for (SdfNormals mode : {SdfNormals::smooth, SdfNormals::analytic}) {
    Shape torus;
    set_sdf_grid(torus, parse_volume_grid_file(bytes.str(), "torus_sdfgrid.vol"), "torus_sdfgrid.vol");
    torus.sdf_normals = mode;
    const TraceableScene scene(scene_of(torus), 4, 4, "");
    for (const MitsubaRay& r : kMitsubaRays) {
      Hit hit;
      const bool found = scene.intersect(Ray{glm::vec3(r.o), glm::vec3(r.d)}, &hit);
      ASSERT_EQ(found, std::isfinite(r.t)) << r.o.x << " " << r.o.y << " " << r.o.z;
      if (!found) continue;
      const double t = glm::length(glm::dvec3(hit.sp.p) - r.o) / glm::length(r.d);
      EXPECT_NEAR(t, r.t, 2e-5);
      EXPECT_GT(glm::dot(glm::dvec3(hit.sp.ng), r.ng), 1 - 1e-5);
      const glm::dvec3 ns = mode == SdfNormals::smooth ? r.ns_smooth : r.ns_analytic;
      EXPECT_GT(glm::dot(glm::dvec3(hit.ns), ns), 1 - 1e-5) << "normals " << int(mode);
    }
  }
}

}  // namespace
}  // namespace tessera
