// Mitsuba's sdfgrid shape as Embree user geometry: the zero set of the trilinear interpolant of
// a grid of values, intersected exactly (a cubic along the ray in each voxel) in double
// precision, with Mitsuba's analytic and smooth normals.
#pragma once

#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

/// Where a ray meets an SDF grid, in the space of the shape (the world, or its group's space).
struct SdfGridHit {
  glm::vec3 p{0.0f};        ///< on the surface (projected onto it in double, then rounded)
  glm::vec3 p_error{0.0f};  ///< |p - exact| <= p_error per coordinate
  glm::vec3 ng{0.0f};       ///< unit gradient of the interpolant: the front, towards growing values
  glm::vec3 ns{0.0f};       ///< unit shading normal (Mitsuba's smooth or analytic normal)
};

/// The render-ready grid. Grid space has sample (i, j, k) at integer point (i, j, k); object
/// space is grid space divided by (n - 1) per axis ([0, 1]^3); the shape's space is object
/// space mapped by Shape::to_world. Primitives are bricks of up to kBrick^3 voxels that hold
/// at least one voxel with a corner value >= 0 and one <= 0 (the only voxels the surface can
/// cross); a brick's bounds are the union of its voxels' tight surface boxes (corners on the
/// surface and crossings of the voxel's edges, Hansson-Söderlund and Akenine-Möller 2023).
class SdfGrid {
 public:
  static constexpr uint32_t kBrick = 4;

  /// `shape` must be a valid Shape::Kind::sdfgrid (core/scene/native/sdfgrid_shape.h).
  explicit SdfGrid(const Shape& shape);

  uint32_t primitive_count() const { return uint32_t(bricks_.size()); }
  /// Brick `primitive`'s box in the shape's space, rounded outward and padded by 1e-3 voxel
  /// (and float rounding) so that Embree's float box tests never cut off a hit.
  RTCBounds bounds(uint32_t primitive) const { return bounds_[primitive]; }

  /// The nearest t in (t_near, t_far] where o + t d (the shape's space) meets the surface in
  /// brick `primitive`, or a negative number; `voxel` gets the voxel's index within the brick's
  /// list. Each voxel is cut out of the ray by a slab test; the values where the ray enters and
  /// leaves it are the interpolant on the crossed face (the same bits in both voxels that share
  /// it, so a surface crossing a face is found by one of them); between them the first sign
  /// change of the cubic along the ray, split at its turning points, is refined by Newton's
  /// method kept inside the bracket.
  double intersect(uint32_t primitive, const glm::dvec3& o, const glm::dvec3& d, double t_near, double t_far,
                   uint32_t* voxel) const;

  /// The hit at t on voxel `voxel` of brick `primitive` (from intersect()).
  SdfGridHit hit(uint32_t primitive, uint32_t voxel, const glm::dvec3& o, const glm::dvec3& d, double t) const;

  /// Value and grid-space gradient of the interpolant in voxel `cell` at local w in [0, 1]^3.
  double eval(const glm::u32vec3& cell, const glm::dvec3& w, glm::dvec3* gradient) const;
  /// Mitsuba's smooth normal at grid-space point `pg` (not normalised, object-space units).
  glm::dvec3 smooth_gradient(const glm::dvec3& pg) const;

 private:
  struct Brick {
    uint32_t first = 0;  ///< into voxels_
    uint32_t count = 0;
  };
  float value(int64_t x, int64_t y, int64_t z) const;
  double intersect_voxel(const glm::u32vec3& cell, const glm::dvec3& og, const glm::dvec3& dg, double t_near,
                         double t_far) const;

  glm::u32vec3 n_{0};                 ///< samples per axis
  std::vector<float> values_;         ///< x fastest
  std::vector<glm::u32vec3> voxels_;  ///< surface voxels (lower corner), grouped by brick
  std::vector<Brick> bricks_;
  std::vector<RTCBounds> bounds_;
  glm::dmat4 grid_from_shape_{1.0};  ///< the shape's space to grid space
  glm::dmat4 shape_from_grid_{1.0};
  glm::dmat3 normal_to_shape_{1.0};  ///< object-space gradient to the shape's space
  glm::dvec3 resolution_{1.0};       ///< n - 1 per axis
  SdfNormals normals_ = SdfNormals::smooth;
};

/// Attaches the bounds, intersect and occluded callbacks of `grid` (which must outlive the
/// Embree geometry) to a RTC_GEOMETRY_TYPE_USER geometry. A hit's u is the voxel's index in
/// its brick (a small integer, exact in float), v is 0.
void attach_sdf_grid_callbacks(RTCGeometry geometry, const SdfGrid* grid);

}  // namespace tessera
