// Russian roulette (path_vertex.h, volpath.cpp): it starts at the scene's rr_depth; it spares
// the first kFreeSpecularVertices delta vertices in a row, so light carried through glass is not
// thinned at the glass, and applies again after them, so a path trapped by total internal
// reflection still ends.
#include <gtest/gtest.h>

#include "render/integrators/path_vertex.h"
#include "render/integrators/volpath.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

/// How many of `n` paths, aimed at the unit sphere of `s` and arriving there as `start` says
/// (vertex, throughput, ...), end at that vertex (path_vertex returns false).
int paths_ended_at_sphere(const Scene& s, const PathState& start, uint32_t n) {
  const TraceableScene scene(s, 4, 4, "");
  int ended = 0;
  for (uint32_t i = 0; i < n; ++i) {
    PathState path = start;
    path.ray = Ray{glm::vec3(0.1f, 0.2f, 5.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
    Hit hit;
    if (!scene.intersect(path.ray, &hit)) ADD_FAILURE() << "the ray misses the sphere";
    PixelSampler sampler(7, 0, 0, i);
    ShadowQuery shadow;
    bool has_shadow;
    if (!path_vertex(scene, -1, sampler, path, &hit, &shadow, &has_shadow)) ++ended;
  }
  return ended;
}

/// How many of `n` paths that reach a smooth glass sphere at vertex 6 with throughput 0.05
/// (survival 0.05 wherever roulette applies) end there, having already scattered at
/// `specular_run` delta vertices in a row.
int paths_ended_at_glass(int specular_run, uint32_t n) {
  Scene s;
  s.shapes.push_back(test::sphere({0, 0, 0}, 1.0, test::add_material(s, MaterialType::glass, 1.5)));
  PathState start{Ray{}};
  start.vertex = 6;
  start.beta = glm::vec3(0.05f);
  start.prev_delta = true;
  start.specular_run = specular_run;
  return paths_ended_at_sphere(s, start, n);
}

TEST(Roulette, SparesTheFirstSpecularVerticesInARow) {
  // Before the rule, about 95 % of these paths ended at the glass.
  for (int run = 0; run < path_vertex_detail::kFreeSpecularVertices; ++run) {
    EXPECT_EQ(paths_ended_at_glass(run, 1000), 0) << run << " delta vertices before";
  }
}

TEST(Roulette, AppliesAgainAfterThemSoTrappedPathsEnd) {
  // Survival 0.05: about 950 of 1000 end; at least 900 with overwhelming probability.
  EXPECT_GT(paths_ended_at_glass(path_vertex_detail::kFreeSpecularVertices, 1000), 900);
}

/// How many of `n` paths that reach a diffuse sphere (albedo 0.5) at vertex `vertex` with
/// throughput 0.05 end there, in a scene whose Russian roulette starts at `rr_depth`: only
/// roulette can end them (a cosine-weighted bounce never falls below the surface).
int paths_ended_at_diffuse(int rr_depth, int vertex, uint32_t n) {
  Scene s;
  s.render.rr_depth = rr_depth;
  s.shapes.push_back(test::sphere({0, 0, 0}, 1.0, test::add_diffuse(s, glm::dvec3(0.5))));
  PathState start{Ray{}};
  start.vertex = vertex;
  start.beta = glm::vec3(0.05f);
  return paths_ended_at_sphere(s, start, n);
}

TEST(Roulette, StartsAtTheScenesRrDepth) {
  // Vertex 6 is the path's seventh scattering event: roulette applies from rr_depth 7 down, as
  // Mitsuba's path integrator (depth >= rr_depth after the event). Survival 0.025: about 975
  // of 1000 end where it applies, at least 900 with overwhelming probability.
  EXPECT_EQ(paths_ended_at_diffuse(1000, 6, 1000), 0);
  EXPECT_EQ(paths_ended_at_diffuse(8, 6, 1000), 0);
  EXPECT_GT(paths_ended_at_diffuse(7, 6, 1000), 900);
  EXPECT_GT(paths_ended_at_diffuse(1, 6, 1000), 900);
  // rr_depth 1: even at the camera ray's hit; the default (3) spares the first two vertices.
  EXPECT_GT(paths_ended_at_diffuse(1, 0, 1000), 900);
  EXPECT_EQ(paths_ended_at_diffuse(kDefaultRrDepth, 1, 1000), 0);
  EXPECT_GT(paths_ended_at_diffuse(kDefaultRrDepth, 2, 1000), 900);
}

/// Closest-hit queries of `n` volumetric paths with max_depth 20 from the centre of a lossless
/// fog (sigma_t 10, albedo 1) a thousand units wide, whose roulette starts at `rr_depth`:
/// without roulette each path scatters 20 times (20 queries) and never reaches the boundary.
uint64_t volume_path_queries(int rr_depth, uint32_t n) {
  Scene s;
  s.render.rr_depth = rr_depth;
  s.camera.medium = 0;
  Medium fog;
  fog.name = "fog";
  fog.sigma_t.value = glm::dvec3(10);
  fog.albedo.value = glm::dvec3(1);
  s.media.push_back(fog);
  Shape boundary = test::sphere({0, 0, 0}, 1000.0, test::add_diffuse(s, glm::dvec3(0.5)));
  boundary.interior = 0;
  s.shapes.push_back(boundary);
  const TraceableScene scene(s, 4, 4, "");
  PathCounters counters;
  for (uint32_t i = 0; i < n; ++i) {
    PixelSampler sampler(7, 0, 0, i);
    const Ray ray{glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
    trace_volume_path(scene, ray, 20, sampler, counters);
  }
  return counters.rays;
}

TEST(Roulette, VolumetricPathsStartItAtTheScenesRrDepth) {
  // Survival 0.95 (throughput 1) wherever roulette applies: from rr_depth 19 on it applies
  // once, after the 19th event (about 20 of 400 paths end there; none with probability
  // 1e-9); from 1000 never.
  EXPECT_EQ(volume_path_queries(1000, 400), 20u * 400);
  EXPECT_EQ(volume_path_queries(20, 400), 20u * 400);
  EXPECT_LT(volume_path_queries(19, 400), 20u * 400);
  EXPECT_LT(volume_path_queries(kDefaultRrDepth, 400), volume_path_queries(19, 400));
}

}  // namespace
}  // namespace tessera
