// Mitsuba's area emitter: an emitting shape (triangles or a sphere) of constant or textured
// radiance, sampled uniformly by area (solid-angle sampling of spheres and triangles is future
// work, docs/renderer.md).
#pragma once

#include <cstdint>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/geometry.h"
#include "render/light/light_sample.h"
#include "render/light/piecewise_constant.h"

namespace tessera {

/// The value of scene texture `texture` (an index into Scene::textures) at (u, v): the light
/// code's view of the renderer's texture set (TextureSet::lookup).
using TextureLookup = std::function<glm::vec3(int32_t texture, glm::vec2 uv)>;

/// The (u, v) of a point on a sphere, Mitsuba's parametrisation: with dir = frame^-1 (p - c)
/// normalised, u = phi / (2 pi) in [0, 1) (phi = atan2(dir.y, dir.x)), v = theta / pi
/// (theta = acos(dir.z)).
glm::vec2 sphere_uv(const glm::mat3& frame, glm::vec3 dir);

class AreaLight {
 public:
  /// `g` (an emitter: emission > 0) must outlive the light; `textures` is called when
  /// g.emission_texture >= 0 and must then be set (the light keeps a copy).
  AreaLight(const Geometry& g, TextureLookup textures);

  /// A point uniform by area on the shape from u in [0,1)^2, with its error bound, its
  /// front-facing unit normal and its (u, v) (triangles: interpolated vertex uvs, (0, 0)
  /// without them; spheres: sphere_uv).
  struct PointSample {
    SurfacePoint sp;
    glm::vec2 uv{0.0f};
  };
  PointSample sample_point(glm::vec2 u) const;

  /// A point for ref (light-pick probability NOT included): pdf = d^2 / (|cos| area); pdf 0
  /// when the point sends nothing towards ref (its back, a black texel) or lies on ref.
  LightSample sample(glm::vec3 ref, glm::vec2 u) const;
  /// Radiance leaving the surface point with front-facing normal ng and texture coordinates
  /// uv towards w: emission * texture(uv) when w is on the front (or emission is two-sided),
  /// 0 otherwise.
  glm::vec3 emitted(glm::vec2 uv, glm::vec3 ng, glm::vec3 w) const;
  /// The solid-angle density sample() gives the point hit_p (normal hit_ng, either
  /// orientation) seen from ref, pick probability not included; 0 for a grazing point.
  float pdf(glm::vec3 ref, glm::vec3 hit_p, glm::vec3 hit_ng) const;
  /// Emitted power, luminance-weighted: pi * area * L (twice for two-sided emission), L the
  /// emission times the mean of the texture over 16 x 16 points of [0,1)^2. The figure only
  /// steers light picking; when that mean is 0 the untextured emission stands in for it, so a
  /// light lit only between the probe points still gets picked.
  double power() const;
  float area() const { return area_; }
  const Geometry& geometry() const { return *g_; }

 private:
  const Geometry* g_;
  TextureLookup textures_;
  PiecewiseConstant1D triangles_;  ///< by area
  float area_ = 0;
};

}  // namespace tessera
