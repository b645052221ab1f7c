// Shape groups placed by instances trace exactly like the same shapes written out in the world,
// and their hits report the world-space point, normals and uv tangents.
#include <random>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// A box and a sphere in a group, placed twice, against the same shapes moved to the world.
struct Pair {
  Scene instanced, flat;
};

Shape moved(Shape s, const glm::dmat4& m) {
  for (glm::dvec3& p : s.positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  s.center = glm::dvec3(m * glm::dvec4(s.center, 1.0));
  s.radius *= glm::length(glm::dvec3(m[0]));  // the transforms below are similarities
  s.frame = glm::dmat3(m) / glm::length(glm::dvec3(m[0])) * s.frame;
  return s;
}

Pair make_pair() {
  Pair p;
  for (Scene* s : {&p.instanced, &p.flat}) {
    test::add_diffuse(*s, {0.5, 0.5, 0.5});
    s->textures.push_back(Texture{});  // asks the scene for uvs (the hits then carry them)
    s->textures.back().kind = TextureKind::checkerboard;
  }
  ShapeGroup group;
  group.name = "g";
  group.origin = "group";
  group.shapes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, 0, false));
  group.shapes.back().uvs.assign(group.shapes.back().positions.size(), glm::dvec2(0));
  for (size_t i = 0; i < group.shapes.back().uvs.size(); ++i) {
    group.shapes.back().uvs[i] = {double(i % 3) * 0.5, double(i % 2)};
  }
  group.shapes.push_back(test::sphere({3, 0, 0}, 0.75, 0));
  p.instanced.groups.push_back(group);
  const glm::dmat4 a = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -6)) *
                       glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0.3, 1, 0.2)) *
                       glm::scale(glm::dmat4(1.0), glm::dvec3(1.5));
  const glm::dmat4 b = glm::translate(glm::dmat4(1.0), glm::dvec3(-4, 2, -9)) *
                       glm::rotate(glm::dmat4(1.0), -1.9, glm::dvec3(1, 0.1, 0.4));
  for (const glm::dmat4& m : {a, b}) {
    Shape inst;
    inst.kind = Shape::Kind::instance;
    inst.group = 0;
    inst.to_world = m;
    inst.origin = "instance";
    p.instanced.shapes.push_back(inst);
    for (const Shape& s : group.shapes) p.flat.shapes.push_back(moved(s, m));
  }
  return p;
}

TEST(Instances, HitLikeTheShapesMovedToTheWorld) {
  const Pair p = make_pair();
  const TraceableScene instanced(p.instanced, 4, 4, "");
  const TraceableScene flat(p.flat, 4, 4, "");
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 d = square_to_uniform_sphere({u(rng), u(rng)});
    const Ray ray{{0.0f, 0.5f, 0.0f}, d};
    Hit a, b;
    const bool ha = instanced.intersect(ray, &a), hb = flat.intersect(ray, &b);
    // Rays that graze an edge may differ; the rest must agree.
    if (ha != hb) continue;
    if (!ha) continue;
    ++hits;
    const float scale = std::max(1.0f, glm::length(b.sp.p));
    EXPECT_LT(glm::length(a.sp.p - b.sp.p), 1e-4f * scale);
    EXPECT_GT(glm::dot(a.sp.ng, b.sp.ng), 0.9999f);
    EXPECT_GT(glm::dot(a.ns, b.ns), 0.9999f);
    EXPECT_NEAR(a.uv.x, b.uv.x, 1e-3f);
    EXPECT_NEAR(a.uv.y, b.uv.y, 1e-3f);
    EXPECT_LT(glm::length(a.dpdu - b.dpdu), 1e-3f * std::max(1.0f, glm::length(b.dpdu)));
    EXPECT_LT(glm::length(a.dpdv - b.dpdv), 1e-3f * std::max(1.0f, glm::length(b.dpdv)));
    // The error bound holds the point and spawned rays leave the surface.
    const glm::vec3 w = square_to_uniform_sphere({u(rng), u(rng)});
    Hit again;
    const Ray spawned{offset_ray_origin(a.sp, w), w, 1e-3f};
    EXPECT_FALSE(instanced.intersect(spawned, &again) && again.geometry == a.geometry &&
                 again.primitive == a.primitive && glm::length(again.sp.p - a.sp.p) < 1e-4f);
  }
  EXPECT_GT(hits, 500);  // 762 with this seed
}

TEST(Instances, RefusedInsideGroupsAndOutOfRange) {
  Pair p = make_pair();
  p.instanced.shapes[0].group = 7;
  EXPECT_THROW(TraceableScene(p.instanced, 4, 4, ""), SceneError);
}

}  // namespace
}  // namespace tessera
