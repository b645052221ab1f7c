// The packet tracer gives the same bits whatever its packet width, and the same hits as
// single-ray queries, on the repository's scenes and on exact spheres.
#include "render/scene/packet_tracer.h"

#include <bit>
#include <functional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "render/geometry/sphere_intersector.h"
#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

struct Bounds {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
};

Bounds scene_bounds(const Scene& s) {
  Bounds b;
  for (const Shape& sh : s.shapes) {
    if (sh.kind == Shape::Kind::sphere) {
      b.lo = glm::min(b.lo, glm::vec3(sh.center - sh.radius));
      b.hi = glm::max(b.hi, glm::vec3(sh.center + sh.radius));
    }
    for (const glm::dvec3& p : sh.positions) {
      b.lo = glm::min(b.lo, glm::vec3(p));
      b.hi = glm::max(b.hi, glm::vec3(p));
    }
  }
  return b;
}

/// `count` rays: half from random points of the (slightly grown) scene box in uniform
/// directions, half leaving the hit points of those rays (found with rtcIntersect1) from the
/// surface itself (unless !from_hits), so ties at t near 0 are exercised; a quarter have a
/// finite t_max, one in eleven is inactive.
RayBatch random_rays(RTCScene scene, const Bounds& b, size_t count, uint32_t seed, bool from_hits = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::vec3 size = b.hi - b.lo;
  const float diagonal = glm::length(size);
  PacketTracer single(scene, 1);
  RayBatch rays;
  rays.resize(count);
  HitBatch hit;
  hit.resize(1);
  for (size_t i = 0; i < count; ++i) {
    Ray r;
    r.o = b.lo - 0.1f * size + 1.2f * size * glm::vec3(u(rng), u(rng), u(rng));
    r.d = square_to_uniform_sphere({u(rng), u(rng)});
    if (from_hits && i % 2 == 1) {
      // From the previous ray's hit point, if it hit something.
      const Ray prev = rays.get(i - 1);
      RayBatch one;
      one.resize(1);
      one.set(0, {prev.o, prev.d});
      single.intersect(one, 0, 1, &hit);
      if (hit.geometry[0] != RTC_INVALID_GEOMETRY_ID) r.o = prev.o + hit.t[0] * prev.d;
    }
    if (u(rng) < 0.25f) r.t_max = u(rng) * diagonal;
    rays.set(i, r);
    rays.active[i] = i % 11 == 5 ? 0 : 1;
  }
  return rays;
}

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

/// Traces `rays` at every width (in ranges that do not start on a packet boundary) and expects
/// the same bits as width 1. Returns how many rays hit something `counted(geometry, instance)`.
int expect_same_at_every_width(RTCScene scene, const RayBatch& rays, const std::string& name,
                               const std::function<bool(uint32_t, uint32_t)>& counted) {
  const size_t n = rays.size();
  HitBatch reference;
  reference.resize(n);
  std::vector<uint8_t> reference_blocked(n);
  const PacketTracer single(scene, 1);
  single.intersect(rays, 0, n, &reference);
  single.occluded(rays, 0, n, &reference_blocked);
  int sphere_hits = 0, blocked = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t g = reference.geometry[i];
    if (g != RTC_INVALID_GEOMETRY_ID && counted(g, reference.instance[i])) ++sphere_hits;
    blocked += reference_blocked[i];
    if (!rays.active[i]) {
      EXPECT_EQ(g, RTC_INVALID_GEOMETRY_ID) << name << " inactive ray " << i;
      EXPECT_EQ(reference_blocked[i], 0) << name << " inactive ray " << i;
    }
  }
  EXPECT_GT(blocked, 0) << name;
  for (int width : {4, 8, 16}) {
    const PacketTracer tracer(scene, width);
    HitBatch hits;
    hits.resize(n);
    std::vector<uint8_t> occluded(n, 7);
    // Three ranges, the middle one starting off a packet boundary and ending in a short tail.
    const size_t cut1 = 3, cut2 = n - 5;
    for (auto [begin, end] : {std::pair{size_t(0), cut1}, {cut1, cut2}, {cut2, n}}) {
      tracer.intersect(rays, begin, end, &hits);
      tracer.occluded(rays, begin, end, &occluded);
    }
    int differences = 0;
    for (size_t i = 0; i < n && differences < 5; ++i) {
      const bool same = hits.geometry[i] == reference.geometry[i] && occluded[i] == reference_blocked[i] &&
                        (hits.geometry[i] == RTC_INVALID_GEOMETRY_ID ||
                         (hits.primitive[i] == reference.primitive[i] && hits.instance[i] == reference.instance[i] &&
                          bits(hits.t[i]) == bits(reference.t[i]) &&
                          bits(hits.u[i]) == bits(reference.u[i]) && bits(hits.v[i]) == bits(reference.v[i]) &&
                          bits(hits.ng_x[i]) == bits(reference.ng_x[i]) &&
                          bits(hits.ng_y[i]) == bits(reference.ng_y[i]) &&
                          bits(hits.ng_z[i]) == bits(reference.ng_z[i])));
      if (!same) {
        ++differences;
        ADD_FAILURE() << name << ", width " << width << ", ray " << i << ": geometry " << hits.geometry[i]
                      << " primitive " << hits.primitive[i] << " t " << hits.t[i] << " u " << hits.u[i]
                      << " v " << hits.v[i] << " occluded " << int(occluded[i]) << "; width 1: geometry "
                      << reference.geometry[i] << " primitive " << reference.primitive[i] << " t "
                      << reference.t[i] << " u " << reference.u[i] << " v " << reference.v[i] << " occluded "
                      << int(reference_blocked[i]);
      }
    }
  }
  return sphere_hits;
}

class PacketTracerScenes : public ::testing::TestWithParam<const char*> {};

TEST_P(PacketTracerScenes, EveryWidthGivesTheSameBits) {
  const Scene s = load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/scenes/" + GetParam());
  for (const std::string isa : {"", "avx2", "sse4.2"}) {
    const TraceableScene scene(s, 64, 64, isa);
    const RayBatch rays = random_rays(scene.embree_scene(), scene_bounds(s), 20000, 3);
    expect_same_at_every_width(scene.embree_scene(), rays, std::string(GetParam()) + " isa '" + isa + "'",
                               [](uint32_t, uint32_t) { return true; });
  }
}

TEST_P(PacketTracerScenes, PacketsHitWhatTheRendererHits) {
  // Packets of the renderer's own Embree scene find the hits of TraceableScene::intersect.
  const Scene s = load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/scenes/" + GetParam());
  const TraceableScene traceable(s, 64, 64, "");
  const RayBatch rays = random_rays(traceable.embree_scene(), scene_bounds(s), 5000, 7);
  HitBatch hits;
  hits.resize(rays.size());
  PacketTracer(traceable.embree_scene(), PacketTracer::native_width(traceable.embree_device()))
      .intersect(rays, 0, rays.size(), &hits);
  int compared = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!rays.active[i]) continue;
    Hit hit;
    const bool found = traceable.intersect(rays.get(i), &hit);
    ASSERT_EQ(found, hits.geometry[i] != RTC_INVALID_GEOMETRY_ID) << GetParam() << " ray " << i;
    if (!found) continue;
    const Geometry& g = traceable.geometry(hits.geometry[i]);
    EXPECT_EQ(hit.geometry->kind, g.kind) << GetParam() << " ray " << i;
    EXPECT_EQ(hit.primitive, hits.primitive[i]) << GetParam() << " ray " << i;
    const Ray r = rays.get(i);
    const glm::vec3 p = r.o + hits.t[i] * r.d;
    EXPECT_LE(glm::length(p - hit.sp.p), 1e-4f * (1.0f + glm::length(p))) << GetParam() << " ray " << i;
    ++compared;
  }
  EXPECT_GT(compared, 1000) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Scenes, PacketTracerScenes,
                         ::testing::Values("cornell.json", "cornell-sphere.json", "hexroom.json", "bunny.json"));

TEST(PacketTracer, SpheresGiveTheSameBitsAtEveryWidth) {
  // Spheres of several sizes overlapping a box; the user-geometry callbacks see N = 4, 8, 16.
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  s.shapes.push_back(test::box({-2, -2, -2}, {2, 2, 2}, m, true));
  s.shapes.push_back(test::sphere({0.3, -0.4, 0.2}, 1.1, m));
  s.shapes.push_back(test::sphere({-1.2, 1.0, -0.5}, 0.4, m));
  s.shapes.push_back(test::sphere({1.0, 1.0, 1.0}, 0.05, m));
  s.shapes.push_back(test::sphere({0.0, 0.0, 0.0}, 1.9, m, true));
  const TraceableScene scene(s, 64, 64, "");
  const RayBatch rays = random_rays(scene.embree_scene(), scene_bounds(s), 20000, 11);
  const auto is_sphere = [&](uint32_t g, uint32_t) { return scene.geometry(g).kind == Geometry::Kind::sphere; };
  EXPECT_GT(expect_same_at_every_width(scene.embree_scene(), rays, "spheres", is_sphere), 5000);
}

TEST(PacketTracer, SphereNormalIsTheHitPointLessTheCentre) {
  // The callbacks report Embree's Ng unnormalised (no division by the radius): the hit point
  // less the centre, so outward and as long as the radius, at every width.
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  s.shapes.push_back(test::sphere({0.3, -0.4, 0.2}, 1.1, m));
  s.shapes.push_back(test::sphere({-1.2, 1.0, -0.5}, 0.4, m));
  const TraceableScene scene(s, 64, 64, "");
  const RayBatch rays = random_rays(scene.embree_scene(), scene_bounds(s), 4000, 5, false);
  for (const int width : {1, 16}) {
    const PacketTracer tracer(scene.embree_scene(), width);
    HitBatch hits;
    hits.resize(rays.size());
    tracer.intersect(rays, 0, rays.size(), &hits);
    int checked = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      if (hits.geometry[i] == RTC_INVALID_GEOMETRY_ID) continue;
      const Geometry& g = scene.geometry(hits.geometry[i]);
      const Ray r = rays.get(i);
      const glm::dvec3 p = glm::dvec3(r.o) + double(hits.t[i]) * glm::dvec3(r.d);
      const glm::dvec3 ng(hits.ng_x[i], hits.ng_y[i], hits.ng_z[i]);
      EXPECT_NEAR(glm::length(ng), g.radius, 1e-5 * g.radius) << "width " << width << " ray " << i;
      EXPECT_LT(glm::length(ng - (p - g.center)), 1e-4 * g.radius) << "width " << width << " ray " << i;
      ++checked;
    }
    EXPECT_GT(checked, 500) << "width " << width;
  }
}

TEST(PacketTracer, InstancedSpheresAndMeshesGiveTheSameBitsAtEveryWidth) {
  // A group (a box and a sphere) placed twice by Embree instances, beside a plain sphere: the
  // sphere callbacks then run inside instance traversal, N lanes at a time.
  RTCDevice device = rtcNewDevice(nullptr);
  ASSERT_NE(device, nullptr);
  Scene group_shapes;
  const uint32_t m = test::add_diffuse(group_shapes, {0.5, 0.5, 0.5});
  group_shapes.shapes.push_back(test::box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}, m, false));
  const Shape box = group_shapes.shapes[0];
  std::vector<glm::vec3> positions(box.positions.begin(), box.positions.end());
  Geometry sphere, plain;
  sphere.kind = plain.kind = Geometry::Kind::sphere;
  sphere.center = {0.3, 0.8, 0.1};
  sphere.radius = 0.45;
  plain.center = {0.0, -1.0, 0.0};
  plain.radius = 0.7;

  RTCScene group = rtcNewScene(device);
  rtcSetSceneFlags(group, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry tris = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(tris, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions.data(), 0,
                             sizeof(glm::vec3), positions.size());
  rtcSetSharedGeometryBuffer(tris, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, box.indices.data(), 0,
                             sizeof(glm::u32vec3), box.indices.size());
  rtcCommitGeometry(tris);
  rtcAttachGeometry(group, tris);  // id 0
  rtcReleaseGeometry(tris);
  RTCGeometry user = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  attach_sphere_callbacks(user, &sphere);
  rtcCommitGeometry(user);
  rtcAttachGeometry(group, user);  // id 1
  rtcReleaseGeometry(user);
  rtcCommitScene(group);

  RTCScene top = rtcNewScene(device);
  rtcSetSceneFlags(top, RTC_SCENE_FLAG_ROBUST);
  for (float x : {-1.2f, 1.2f}) {
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, group);
    // Column-major 3x4: a rotation about y by 30 degrees and a translation by x.
    const float c = 0.8660254f, sn = 0.5f;
    const float xfm[12] = {c, 0, -sn, 0, 1, 0, sn, 0, c, x, 0.2f, 0};
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(instance);
    rtcAttachGeometry(top, instance);  // ids 0, 1
    rtcReleaseGeometry(instance);
  }
  RTCGeometry lone = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  attach_sphere_callbacks(lone, &plain);
  rtcCommitGeometry(lone);
  rtcAttachGeometry(top, lone);  // id 2
  rtcReleaseGeometry(lone);
  rtcCommitScene(top);

  Bounds b;
  b.lo = {-2.5f, -2.0f, -1.5f};
  b.hi = {2.5f, 1.5f, 1.5f};
  // Not from hit points: a ray starting exactly on an instanced surface can be found occluded
  // (a self-hit at t = 0) by Embree's packets and not by rtcOccluded1 (packet_tracer.h).
  const RayBatch rays = random_rays(top, b, 20000, 13, false);
  const int instanced_spheres = expect_same_at_every_width(
      top, rays, "instances", [](uint32_t g, uint32_t instance) { return instance != RTC_INVALID_GEOMETRY_ID && g == 1; });
  EXPECT_GT(instanced_spheres, 300);  // 447 with these seeds
  rtcReleaseScene(top);
  rtcReleaseScene(group);
  rtcReleaseDevice(device);
}

TEST(PacketTracer, InactiveAndTailRaysAreNotTraced) {
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  s.shapes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, m, true));
  const TraceableScene scene(s, 64, 64, "");
  RayBatch rays;
  rays.resize(21);
  for (size_t i = 0; i < rays.size(); ++i) rays.set(i, {{0, 0, 0}, {0, 0, 1}});
  rays.active[2] = 0;
  for (int width : {1, 4, 8, 16}) {
    const PacketTracer tracer(scene.embree_scene(), width);
    HitBatch hits;
    hits.resize(rays.size());
    std::vector<uint8_t> occluded(rays.size(), 0);
    tracer.intersect(rays, 1, 20, &hits);
    tracer.occluded(rays, 1, 20, &occluded);
    for (size_t i = 0; i < rays.size(); ++i) {
      const bool traced = i >= 1 && i < 20 && i != 2;
      EXPECT_EQ(hits.geometry[i] != RTC_INVALID_GEOMETRY_ID, traced) << "width " << width << " ray " << i;
      EXPECT_EQ(occluded[i], traced ? 1 : 0) << "width " << width << " ray " << i;
      if (traced) {
        // Within 4 ulps: Embree's AVX2 kernels give 1 - 2^-24 here, its AVX-512 ones 1.
        EXPECT_FLOAT_EQ(hits.t[i], 1.0f) << "width " << width << " ray " << i;
      }
    }
  }
}

TEST(PacketTracer, RefusesWidthsEmbreeHasNoQueryFor) {
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
  s.shapes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, m, true));
  const TraceableScene scene(s, 64, 64, "");
  EXPECT_THROW(PacketTracer(scene.embree_scene(), 2), std::invalid_argument);
  EXPECT_THROW(PacketTracer(scene.embree_scene(), 32), std::invalid_argument);
  const int native = PacketTracer::native_width(scene.embree_device());
  EXPECT_TRUE(native == 4 || native == 8 || native == 16) << native;
}

}  // namespace
}  // namespace tessera
