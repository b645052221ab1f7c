// Mitsuba's envmap emitter: an infinitely distant environment given as a latitude-longitude
// image (mitsuba3 src/emitters/envmap.cpp), importance sampled by its luminance.
//
// Layout (Mitsuba's): a direction d in the map's frame (to_world^-1 d) has
//   u = atan2(d.x, -d.z) / (2 pi),   v = acos(d.y) / pi,
// so +y is the top row (v = 0) and -z the left edge. Texel columns sit at u = (x + 0.5) / W and
// rows at v = y / (H - 1) (the first and last rows are the poles); radiance is bilinear between
// them, wrapping around in u. A map of one row is constant in v.
//
// Sampling: the cells between neighbouring texels (W x (H-1)) are picked with probability
// proportional to the mean luminance of their four corners times their solid angle, then a
// direction uniform in solid angle inside the cell. The density is therefore piecewise
// constant in solid angle, exactly what pdf() returns, and never zero where the bilinear
// radiance is not (a cell whose corners are all black has zero radiance everywhere in it).
#pragma once

#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "render/light/piecewise_constant.h"
#include "scene/file_reader.h"
#include "scene/scene.h"

namespace tessera {

class EnvmapLight {
 public:
  /// Decodes light.file (EXR, HDR or any format OpenImageIO reads; 8-bit sRGB images are
  /// linearised) from the bytes `reader` returns, through OpenImageIO's in-memory reader.
  /// Throws SceneError naming light.origin and the file when it cannot be decoded or a texel is
  /// NaN, infinite or negative.
  static EnvmapLight from_file(const Light& light, const FileReader& reader);

  /// A map of width x height linear RGB texels, row-major from the top row (v = 0), 3 floats
  /// each. Throws SceneError naming light.origin and light.file on an empty map, a size that
  /// does not match, or a NaN, infinite or negative texel or scale.
  EnvmapLight(const Light& light, uint32_t width, uint32_t height, std::vector<float> rgb);

  /// Radiance arriving from world direction d (unit, pointing away from the scene):
  /// scale * bilinear texel lookup, as Mitsuba's eval.
  glm::vec3 radiance(glm::vec3 d) const;
  /// A world direction from u in [0,1)^2; `pdf` receives its solid-angle density, 0 when the
  /// whole map is black (the direction is then meaningless).
  glm::vec3 sample(glm::vec2 u, float* pdf) const;
  /// The solid-angle density sample() gives world direction d.
  float pdf(glm::vec3 d) const;
  /// Power through the scene's bounding disc, luminance-weighted: pi r^2 times the integral of
  /// luminance over the sphere (the sampling distribution's total).
  double power(double scene_radius) const;

 private:
  glm::vec3 texel(uint32_t x, uint32_t y) const;
  /// (u, v) of a direction in the map's frame.
  glm::vec2 direction_to_uv(glm::vec3 world_d) const;
  /// The sampling cell holding (u, v).
  glm::u32vec2 cell_of(glm::vec2 uv) const;

  uint32_t width_ = 0, height_ = 0;  ///< height >= 2 (a one-row map is stored twice)
  std::vector<float> rgb_;
  glm::vec3 scale_;
  glm::mat3 to_world_, to_local_;
  std::vector<double> cos_theta_;   ///< per row, cos(pi y / (H - 1))
  std::vector<double> cell_omega_;  ///< per row of cells: solid angle of one cell
  PiecewiseConstant2D distribution_;
};

}  // namespace tessera
