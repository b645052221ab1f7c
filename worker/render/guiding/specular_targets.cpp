#include "render/guiding/specular_targets.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <glm/mat3x3.hpp>
#include <string>

#include "accum/accumulation.h"
#include "render/bsdf/material.h"
#include "render/geometry/geometry.h"
#include "render/sampling/warp.h"

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

bool finite(const SpecularImage& i) {
  const float sum = i.center.x + i.center.y + i.center.z + i.radius + i.gate_normal.x + i.gate_normal.y +
                    i.gate_normal.z + i.gate_offset + i.window_center.x + i.window_center.y + i.window_center.z +
                    i.window_radius;
  return std::isfinite(sum) && i.radius > 0 && i.window_radius > 0;
}

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

/// Triangle `tri` of `g` in world space.
void world_triangle(const Geometry& g, const glm::mat4* to_world, const glm::u32vec3& tri, glm::vec3 v[3]) {
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 p = g.positions[tri[k]];
    v[k] = to_world ? glm::vec3(*to_world * glm::vec4(p, 1.0f)) : p;
  }
}

/// The world-space area of a shape (spheres and triangle meshes; 0 for other kinds).
float shape_area(const Geometry& g, const glm::mat4* to_world) {
  if (g.kind == Geometry::Kind::sphere) {
    const SpecularTarget s = shape_sphere(g, to_world);
    return 4.0f * kPi * s.radius * s.radius;
  }
  if (g.kind != Geometry::Kind::triangles) return 0.0f;
  double area = 0;
  for (const glm::u32vec3& tri : g.indices) {
    glm::vec3 v[3];
    world_triangle(g, to_world, tri, v);
    area += 0.5 * glm::length(glm::cross(glm::dvec3(v[1] - v[0]), glm::dvec3(v[2] - v[0])));
  }
  return float(area);
}

}  // namespace

std::vector<std::vector<glm::vec3>> SpecularTargets::flat_faces(const Geometry& g, const glm::mat4* to_world) {
  std::vector<std::vector<glm::vec3>> faces;
  if (g.kind != Geometry::Kind::triangles || g.indices.empty() ||
      g.indices.size() > size_t(kMaxFlatTriangles)) {
    return faces;
  }
  // Triangles in one plane (a quad's two) make one face: unit normals within 1e-4 of each other
  // (either sign) and offsets within 1e-4 of the shape's size.
  std::vector<glm::dvec3> normals;
  std::vector<double> offsets;
  const double size = std::max(1e-30, double(shape_sphere(g, to_world).radius));
  for (const glm::u32vec3& tri : g.indices) {
    glm::vec3 v[3];
    world_triangle(g, to_world, tri, v);
    const glm::dvec3 c = glm::cross(glm::dvec3(v[1] - v[0]), glm::dvec3(v[2] - v[0]));
    const double len = glm::length(c);
    if (!(len > 0)) continue;  // degenerate: no plane
    const glm::dvec3 n = c / len;
    const double o = glm::dot(n, glm::dvec3(v[0]));
    size_t f = 0;
    for (; f < faces.size(); ++f) {
      const double cos_nn = glm::dot(n, normals[f]);
      if (std::abs(cos_nn) > 1 - 1e-4 && std::abs(o * (cos_nn > 0 ? 1 : -1) - offsets[f]) < 1e-4 * size) break;
    }
    if (f == faces.size()) {
      faces.emplace_back();
      normals.push_back(n);
      offsets.push_back(o);
    }
    faces[f].insert(faces[f].end(), v, v + 3);
  }
  return faces;
}

std::optional<SpecularImage> ball_lens_image(glm::vec3 center, float radius, float ior, glm::vec3 lamp,
                                             float lamp_radius) {
  const glm::vec3 to_lamp = lamp - center;
  const float d = glm::length(to_lamp);
  if (!(d > radius) || !(radius > 0) || !(ior > 0) || !(lamp_radius >= 0)) return std::nullopt;
  const glm::vec3 a = to_lamp / d;
  SpecularImage image;
  if (ior == 1.0f) {
    // f infinite: the lamp itself.
    image.center = lamp;
    image.radius = lamp_radius;
  } else {
    const float f = ior * radius / (2.0f * (ior - 1.0f));
    if (!(std::abs(d - f) > 1e-3f * d)) return std::nullopt;  // the image at infinity
    const float d_i = f * d / (d - f);
    image.center = center - a * d_i;
    image.radius = std::abs(d_i) / d * lamp_radius + SpecularTargets::kLensAberration * radius;
  }
  image.gate_normal = -a;
  image.gate_offset = glm::dot(-a, center);
  image.window_center = center;
  image.window_radius = radius;
  if (!finite(image)) return std::nullopt;
  return image;
}

std::optional<SpecularImage> convex_mirror_image(glm::vec3 center, float radius, glm::vec3 lamp, float lamp_radius) {
  const glm::vec3 to_lamp = lamp - center;
  const float d = glm::length(to_lamp);
  if (!(d > radius) || !(radius > 0) || !(lamp_radius >= 0)) return std::nullopt;
  const glm::vec3 a = to_lamp / d;
  // From the vertex (the surface point facing the lamp): object distance d - R, f = -R / 2,
  // image distance f (d - R) / (d - R - f), negative: behind the surface, inside the sphere.
  const float object = d - radius;
  const float f = -0.5f * radius;
  const float d_i = f * object / (object - f);
  SpecularImage image;
  image.center = center + a * (radius + d_i);
  image.radius = std::abs(d_i) / object * lamp_radius + SpecularTargets::kMirrorAberration * radius;
  image.gate_normal = a;
  image.gate_offset = glm::dot(a, center);
  image.window_center = center;
  image.window_radius = radius;
  if (!finite(image)) return std::nullopt;
  return image;
}

std::optional<SpecularImage> flat_mirror_image(const std::vector<glm::vec3>& face, glm::vec3 inside, glm::vec3 lamp,
                                               float lamp_radius) {
  if (face.size() < 3 || !(lamp_radius >= 0)) return std::nullopt;
  // The plane of the face's largest triangle fan (its vertices are in one plane).
  glm::dvec3 c(0.0);
  for (size_t i = 2; i < face.size(); ++i) {
    const glm::dvec3 ci = glm::cross(glm::dvec3(face[i - 1] - face[0]), glm::dvec3(face[i] - face[0]));
    if (glm::dot(ci, ci) > glm::dot(c, c)) c = ci;
  }
  const double len = glm::length(c);
  if (!(len > 0)) return std::nullopt;  // degenerate: no area
  glm::vec3 n(c / len);
  float offset = glm::dot(n, face[0]);
  float s = glm::dot(n, lamp) - offset;
  if (s < 0) {
    n = -n;
    offset = -offset;
    s = -s;
  }
  if (!(s > 0)) return std::nullopt;  // the lamp's centre on the plane
  if (glm::dot(n, inside) - offset > 1e-4f * std::abs(s)) return std::nullopt;  // seen from inside
  const SpecularTarget window = bounding_sphere(face);
  SpecularImage image;
  image.center = lamp - 2.0f * s * n;
  image.radius = lamp_radius;
  image.gate_normal = n;
  image.gate_offset = offset;
  image.window_center = window.center;
  image.window_radius = window.radius;
  if (!finite(image)) return std::nullopt;
  return image;
}

SpecularTargets::SpecularTargets(const std::vector<ShapeRef>& shapes, const std::vector<RenderMaterial>& materials,
                                 float scene_radius) {
  if (!TestSwitch<SpecularTargets>::on()) return;
  std::vector<Candidate> targets;
  std::vector<Lamp> lamps;
  for (const ShapeRef& s : shapes) {
    const Geometry& g = *s.geometry;
    if (g.emission.x > 0 || g.emission.y > 0 || g.emission.z > 0) {
      const SpecularTarget t = shape_sphere(g, s.to_world);
      const float power = float(luminance(g.emission.x, g.emission.y, g.emission.z)) * shape_area(g, s.to_world) *
                          (g.two_sided_emission ? 2.0f : 1.0f);
      if (t.radius > 0 && std::isfinite(t.radius) && power > 0 && std::isfinite(power)) lamps.push_back({t, power});
    }
    if (g.material >= materials.size() || !purely_specular(materials[g.material], materials)) continue;
    const SpecularTarget t = shape_sphere(g, s.to_world);
    if (!(t.radius > 0) || !std::isfinite(t.radius)) continue;
    if (scene_radius > 0 && t.radius > kMaxSceneFraction * scene_radius) continue;
    targets.push_back({t, &g, s.to_world, &materials[g.material]});
  }
  if (targets.size() > size_t(kMaxTargets)) {
    // The largest spheres are kept: they subtend the largest cones from most of the scene.
    std::stable_sort(targets.begin(), targets.end(),
                     [](const Candidate& a, const Candidate& b) { return a.sphere.radius > b.sphere.radius; });
    targets.resize(size_t(kMaxTargets));
  }
  count_ = int(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) {
    lanes_.cx[i] = targets[i].sphere.center.x;
    lanes_.cy[i] = targets[i].sphere.center.y;
    lanes_.cz[i] = targets[i].sphere.center.z;
    lanes_.r[i] = targets[i].sphere.radius;
    lanes_.r2[i] = targets[i].sphere.radius * targets[i].sphere.radius;
  }
  build_images(targets, lamps);
  build_sources();
}

void SpecularTargets::build_images(const std::vector<Candidate>& targets, const std::vector<Lamp>& lamps) {
  struct Scored {
    SpecularImage image;
    float score;
  };
  std::vector<Scored> all;
  // The fraction of a lamp's light that a disc of radius r at distance d, tilted by cos_tilt,
  // intercepts: pi r^2 cos_tilt / (4 pi d^2), capped at one half.
  const auto intercepted = [](float r, float d, float cos_tilt) {
    return std::min(0.5f, r * r * cos_tilt / (4.0f * d * d));
  };
  // A mirror's flat faces and the centroid of their vertices (the inside the faces bound), found
  // once per target, not once per lamp.
  struct Faces {
    std::vector<std::vector<glm::vec3>> faces;
    glm::vec3 inside{0.0f};
  };
  std::vector<Faces> flat(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) {
    const MaterialType type = targets[i].material->type;
    if (type == MaterialType::glass || type == MaterialType::thin_glass) continue;
    flat[i].faces = flat_faces(*targets[i].geometry, targets[i].to_world);
    size_t n = 0;
    for (const auto& face : flat[i].faces) {
      for (const glm::vec3& v : face) flat[i].inside += v;
      n += face.size();
    }
    if (n > 0) flat[i].inside /= float(n);
  }
  for (const Lamp& lamp : lamps) {
    for (size_t i = 0; i < targets.size(); ++i) {
      const Candidate& t = targets[i];
      const MaterialType type = t.material->type;
      const bool refracts = type == MaterialType::glass || type == MaterialType::thin_glass;
      const float d = glm::length(lamp.sphere.center - t.sphere.center);
      if (!(d > 0)) continue;
      if (refracts) {
        // Thin glass bends nothing: its image is the lamp itself (a lens of index 1).
        const float ior = type == MaterialType::glass ? t.material->ior : 1.0f;
        if (auto image = ball_lens_image(t.sphere.center, t.sphere.radius, ior, lamp.sphere.center, lamp.sphere.radius)) {
          all.push_back({*image, lamp.power * intercepted(t.sphere.radius, d, 1.0f)});
        }
        continue;
      }
      const std::vector<std::vector<glm::vec3>>& faces = flat[i].faces;
      if (faces.empty()) {
        if (auto image = convex_mirror_image(t.sphere.center, t.sphere.radius, lamp.sphere.center, lamp.sphere.radius)) {
          all.push_back({*image, lamp.power * intercepted(t.sphere.radius, d, 1.0f)});
        }
        continue;
      }
      for (const auto& face : faces) {
        if (auto image = flat_mirror_image(face, flat[i].inside, lamp.sphere.center, lamp.sphere.radius)) {
          const glm::vec3 to_lamp = lamp.sphere.center - image->window_center;
          const float dist = glm::length(to_lamp);
          if (!(dist > 0)) continue;
          const float cos_tilt = glm::dot(image->gate_normal, to_lamp) / dist;
          all.push_back({*image, lamp.power * intercepted(image->window_radius, dist, cos_tilt)});
        }
      }
    }
  }
  // Largest score first; equal scores keep the order of lamps, then targets, then faces.
  std::stable_sort(all.begin(), all.end(), [](const Scored& a, const Scored& b) { return a.score > b.score; });
  image_count_ = int(std::min(all.size(), size_t(kMaxImages)));
  for (int i = 0; i < image_count_; ++i) images_[i] = all[size_t(i)].image;
}

void SpecularTargets::build_sources() {
  ConeSources& s = sources_;
  const auto add = [&s](const SpecularImage& im, float mass, bool always) {
    const int i = s.count++;
    s.cx[i] = im.center.x;
    s.cy[i] = im.center.y;
    s.cz[i] = im.center.z;
    s.r[i] = im.radius;
    s.r2[i] = im.radius * im.radius;
    s.gx[i] = im.gate_normal.x;
    s.gy[i] = im.gate_normal.y;
    s.gz[i] = im.gate_normal.z;
    s.gate_offset[i] = im.gate_offset;
    s.wx[i] = im.window_center.x;
    s.wy[i] = im.window_center.y;
    s.wz[i] = im.window_center.z;
    s.wr[i] = im.window_radius;
    s.mass[i] = mass;
    s.always[i] = always ? -1 : 0;
  };
  for (int i = 0; i < count_; ++i) {
    SpecularImage self;
    self.center = self.window_center = glm::vec3(lanes_.cx[i], lanes_.cy[i], lanes_.cz[i]);
    self.radius = self.window_radius = lanes_.r[i];
    self.gate_offset = -std::numeric_limits<float>::infinity();
    add(self, kMassFactor, true);
  }
  for (int i = 0; i < image_count_; ++i) add(images_[i], kImageMassFactor, false);
}

SpecularTargets::Lanes SpecularTargets::empty_lanes() {
  Lanes l;
  for (int i = 0; i < kMaxTargets; ++i) {
    l.cx[i] = l.cy[i] = l.cz[i] = l.r[i] = 0.0f;
    l.r2[i] = std::numeric_limits<float>::infinity();
  }
  return l;
}

SpecularTargets::ConeSources SpecularTargets::empty_sources() {
  ConeSources s{};
  for (int i = 0; i < kSourceLanes; ++i) s.gate_offset[i] = std::numeric_limits<float>::infinity();
  return s;
}

}  // namespace tessera
