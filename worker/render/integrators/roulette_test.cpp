// Russian roulette (path_vertex.h): it spares the first kFreeSpecularVertices delta vertices in a
// row, so light carried through glass is not thinned at the glass, and applies again after them,
// so a path trapped by total internal reflection still ends.
#include <gtest/gtest.h>

#include "render/integrators/path_vertex.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

/// How many of `n` paths that reach a smooth glass sphere at vertex 6 with throughput 0.05
/// (survival 0.05 wherever roulette applies) end there, having already scattered at
/// `specular_run` delta vertices in a row.
int paths_ended_at_glass(int specular_run, uint32_t n) {
  Scene s;
  s.shapes.push_back(test::sphere({0, 0, 0}, 1.0, test::add_material(s, MaterialType::glass, 1.5)));
  const TraceableScene scene(s, 4, 4, "");
  int ended = 0;
  for (uint32_t i = 0; i < n; ++i) {
    PathState path{Ray{glm::vec3(0.1f, 0.2f, 5.0f), glm::vec3(0.0f, 0.0f, -1.0f)}};
    path.vertex = 6;
    path.beta = glm::vec3(0.05f);
    path.prev_delta = true;
    path.specular_run = specular_run;
    Hit hit;
    if (!scene.intersect(path.ray, &hit)) ADD_FAILURE() << "the ray misses the sphere";
    PixelSampler sampler(7, 0, 0, i);
    ShadowQuery shadow;
    bool has_shadow;
    if (!path_vertex(scene, -1, sampler, path, &hit, &shadow, &has_shadow)) ++ended;
  }
  return ended;
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

}  // namespace
}  // namespace tessera
