// Mitsuba's area emitter: an emitting shape (triangles or a sphere) of constant or textured
// radiance. Seen from a shading point, a sphere is sampled by the cone of directions it
// subtends and a rectangle (two triangles) by its spherical rectangle, so that the density
// follows the solid angle; other meshes, and rectangles where that does not pay or is not
// accurate, uniformly by area (docs/renderer.md, "Light sampling").
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>

#include "render/geometry/geometry.h"
#include "render/light/light_bounds.h"
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
  /// without them; spheres: sphere_uv). A rectangle maps u to corner + u.x ex + u.y ey
  /// directly (no triangle to pick), other meshes pick a triangle by area with u.x.
  struct PointSample {
    SurfacePoint sp;
    glm::vec2 uv{0.0f};
  };
  PointSample sample_point(glm::vec2 u) const;

  /// A point for ref (light-pick probability NOT included) from u in [0,1)^2, with its
  /// solid-angle density: 1 / (the solid angle) for a sphere seen from outside and for a
  /// rectangle when solid_angle_sampled(ref); otherwise by area, d^2 / (|cos| area). pdf 0
  /// when the point sends nothing towards ref (its back, a black texel) or lies on ref, and
  /// at once, with nothing drawn, where ref is behind() the light.
  /// Inline (LightSet::sample, the path vertex's hot path); solid-angle sampling and meshes
  /// other than rectangles go out of line.
  [[gnu::always_inline]] LightSample sample(glm::vec3 ref, glm::vec2 u) const {
    if (!(area_ > 0)) return {};
    if (sampling_ == Sampling::rectangle) {
      // solid_angle_sampled and behind, on one difference vector.
      // Most points lie in front of the light and more than its diagonal off its plane: by area,
      // from dn alone.
      const Rectangle& r = *rectangle_;
      const glm::vec3 d = ref - r.center;
      const float dn = glm::dot(d, r.normal);
      if (dn < 0 || !r.beyond_diagonal_of_plane(dn)) {
        const float d2 = glm::dot(d, d);
        if (r.behind(d2, dn)) return {};
        if (r.by_solid_angle(d2, dn)) return sample_solid_angle(ref, u);
      }
      return towards(ref, rectangle_point(u.x, u.y), 0.0f);  // sample_point(u) for a rectangle
    }
    if (sampling_ == Sampling::sphere_cone && outside_sphere(ref)) return sample_solid_angle(ref, u);
    return towards(ref, sample_point(u), 0.0f);
  }
  /// Whether sample() draws points by solid angle from ref: for a sphere when ref lies outside
  /// it by more than 1e-3 of its radius (+ 1e-5 of |centre|: points on the sphere itself see
  /// its inside); for a rectangle when ref is at least 1e-5 of the rectangle's diagonal off its
  /// plane (closer, the spherical-rectangle map loses accuracy in double) and the diagonal is at
  /// least the distance to its centre (smaller, d^2 / cos varies too little over the light
  /// for the spherical rectangle's cost to pay: measured on the Cornell box and hexroom,
  /// BENCHMARKS.md); never for other meshes.
  bool solid_angle_sampled(glm::vec3 ref) const {
    if (sampling_ == Sampling::by_area) return false;
    if (sampling_ == Sampling::sphere_cone) return outside_sphere(ref);
    const glm::vec3 d = ref - rectangle_->center;
    return rectangle_->by_solid_angle(glm::dot(d, d), glm::dot(d, rectangle_->normal));
  }
  /// Whether ref lies clearly behind a one-sided rectangle light (by more than 1e-3 of its
  /// diagonal plus its distance to the centre, far more than the rectangle's 1e-5 tolerance and
  /// float rounding): no point of the light sends anything there, so sample() returns nothing
  /// at once and pdf() is 0. False for every other light.
  bool behind(glm::vec3 ref) const {
    if (sampling_ != Sampling::rectangle) return false;
    const glm::vec3 d = ref - rectangle_->center;
    return rectangle_->behind(glm::dot(d, d), glm::dot(d, rectangle_->normal));
  }
  /// Radiance leaving the surface point with front-facing normal ng and texture coordinates
  /// uv towards w: emission * texture(uv) when w is on the front (or emission is two-sided),
  /// 0 otherwise.
  [[gnu::always_inline]] glm::vec3 emitted(glm::vec2 uv, glm::vec3 ng, glm::vec3 w) const {
    // Inline: every light sample and every path that hits an emitter asks.
    const Geometry& g = *g_;
    if (!(glm::dot(ng, w) > 0) && !g.two_sided_emission) return glm::vec3(0.0f);
    if (g.emission_texture < 0) return g.emission;
    return textured_emission(uv);
  }
  /// The solid-angle density sample() gives the point hit_p (a point of the light; normal
  /// hit_ng, either orientation) seen from ref, pick probability not included: the same
  /// figure sample() returns, bit for bit, when sampled by solid angle; by area 0 for a
  /// grazing point.
  float pdf(glm::vec3 ref, glm::vec3 hit_p, glm::vec3 hit_ng) const;
  /// Emitted power, luminance-weighted: pi * area * L (twice for two-sided emission), L the
  /// emission times the mean of the texture over 16 x 16 points of [0,1)^2. The figure only
  /// steers light picking; when that mean is 0 the untextured emission stands in for it, so a
  /// light lit only between the probe points still gets picked.
  double power() const;
  /// Bounds for light picking: the bounding sphere of the shape, power(), and the cone of its
  /// face normals about their area-weighted mean (a sphere, or a mesh whose normals cancel
  /// out: every direction).
  LightBounds bounds() const;
  float area() const { return area_; }
  const Geometry& geometry() const { return *g_; }
  /// Whether the light is a rectangle: two triangles that form one (sampled by solid angle).
  bool is_rectangle() const { return rectangle_.has_value(); }

 private:
  /// Two triangles forming the rectangle corner + [0,1] ex + [0,1] ey: triangle `near`
  /// (corner, corner + ex, corner + ey) and `far` (the opposite corner, corner + ex,
  /// corner + ey); the vertex indices of those corners, so that a point is interpolated on the
  /// very triangle Embree traces.
  struct Rectangle {
    glm::dvec3 corner, ex, ey;
    glm::vec3 center;
    float diagonal = 0;
    float diagonal2 = 0;  ///< diagonal^2: by solid angle within one diagonal of the centre
    float min_plane_distance = 0;  ///< 1e-5 diagonal: closer to the plane, by area
    float center_slack = 0;        ///< 1e-6 |center|: float rounding of the vertices
    bool one_sided = true;         ///< emits on the side of `normal` only
    glm::vec3 normal;  ///< unit

    /// From d2 = |ref - center|^2 and dn = (ref - center) . normal.
    bool by_solid_angle(float d2, float dn) const {
      return diagonal2 >= d2 && std::abs(dn) >= min_plane_distance;
    }
    /// by_solid_angle(|d|^2, dn) when false is already known from dn alone: farther than the
    /// diagonal off the plane (diagonal2 < dn^2 <= d2).
    bool beyond_diagonal_of_plane(float dn) const { return dn * dn > diagonal2; }
    bool behind(float d2, float dn) const {
      return one_sided && dn < 0 && -dn > 1e-3f * (diagonal + std::sqrt(d2)) + center_slack;
    }
    uint32_t near = 0, far = 0;
    uint32_t v_corner = 0, v_x = 0, v_y = 0, v_opposite = 0;
  };
  enum class Sampling : uint8_t { by_area, sphere_cone, rectangle };

  static std::optional<Rectangle> find_rectangle(const Geometry& g);
  /// emission * texture(uv), for a textured emitter.
  glm::vec3 textured_emission(glm::vec2 uv) const;
  /// solid_angle_sampled for a sphere.
  bool outside_sphere(glm::vec3 ref) const;
  /// sample() by solid angle (solid_angle_sampled(ref)).
  LightSample sample_solid_angle(glm::vec3 ref, glm::vec2 u) const;
  /// The point of the rectangle at (a, b) in [0,1]^2: corner + a ex + b ey.
  [[gnu::always_inline]] PointSample rectangle_point(float a, float b) const {
    // Barycentric weights of (a, b) on the near triangle (corner, x, y) or the far one
    // (opposite, x, y): the interpolation of a triangle's points, so the point lies on what
    // Embree traces and carries that triangle's error bound and uvs.
    const Geometry& g = *g_;
    const Rectangle& r = *rectangle_;
    const bool near = a + b <= 1.0f;
    const uint32_t tri = near ? r.near : r.far;
    const uint32_t v0 = near ? r.v_corner : r.v_opposite;
    const float w0 = near ? 1.0f - a - b : a + b - 1.0f;
    const float wx = near ? a : 1.0f - b;
    const float wy = near ? b : 1.0f - a;
    PointSample s;
    s.sp.p = w0 * g.positions[v0] + wx * g.positions[r.v_x] + wy * g.positions[r.v_y];
    s.sp.p_error = glm::vec3(g.point_errors[tri]);
    s.sp.ng = g.face_normals[tri];
    if (!g.uvs.empty()) s.uv = w0 * g.uvs[v0] + wx * g.uvs[r.v_x] + wy * g.uvs[r.v_y];
    return s;
  }
  /// The light sample towards ps from ref: by solid angle with density solid_angle_pdf (> 0),
  /// or by area (solid_angle_pdf == 0).
  [[gnu::always_inline]] LightSample towards(glm::vec3 ref, const PointSample& ps, float solid_angle_pdf) const {
    LightSample s;
    const glm::vec3 to_light = ps.sp.p - ref;
    const float dist2 = glm::dot(to_light, to_light);
    if (!(dist2 > 0)) return s;
    const float distance = std::sqrt(dist2);
    const glm::vec3 wi = to_light / distance;
    const float cos_light = std::abs(glm::dot(ps.sp.ng, wi));
    const glm::vec3 le = emitted(ps.uv, ps.sp.ng, -wi);
    if (!(cos_light > 0) || le == glm::vec3(0.0f)) return s;
    s.wi = wi;
    s.distance = distance;
    s.radiance = le;
    s.pdf = solid_angle_pdf > 0 ? solid_angle_pdf : dist2 / (cos_light * area_);
    s.point = ps.sp;
    return s;
  }

  const Geometry* g_;
  std::optional<Rectangle> rectangle_;
  Sampling sampling_ = Sampling::by_area;
  TextureLookup textures_;
  PiecewiseConstant1D triangles_;  ///< by area
  float area_ = 0;
};

}  // namespace tessera
