// Mitsuba's volume texture: a 3D grid (gridvolume) or a constant (constvolume) looked up at a
// surface point's world position.
#pragma once

#include <memory>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/volume_grid_file.h"
#include "scene/scene.h"

namespace tessera {

/// Lookups as Mitsuba 3's volume texture over its gridvolume (src/textures/volume.cpp,
/// src/volumes/grid.cpp, Dr.Jit's Texture3f without hardware acceleration) makes them in its
/// RGB variants, or over its constvolume (src/volumes/const.cpp).
///
/// Grid: the world point p goes to q = to_local p (to_local = inverse of the texture's
/// volume_to_world), in which the grid spans [0, 1]^3, voxel (x, y, z) covering
/// [x, x+1)/nx x [y, y+1)/ny x [z, z+1)/nz. Trilinear interpolates between voxel centres at
/// q * n - 1/2; nearest takes the voxel holding q * n. Voxel indices outside the grid wrap per
/// axis: clamp (edge voxel), repeat (modulo), mirror (reflected every other period). A colour
/// lookup (eval) reads 1 channel as grey, 3 as RGB; the scalar one (eval_1) reads 1 channel as
/// itself and 3 as their luminance, as Mitsuba's eval_1.
/// Constant: eval gives the value; eval_1 the value of 1 channel, the mean of 3 (Mitsuba's
/// constvolume: eval_1 is its value's mean()).
///
/// Float arithmetic in Dr.Jit's order, so results agree with Mitsuba to rounding. A non-finite
/// q reads as q = 0; q far outside the grid is wrapped without integer overflow. Immutable:
/// thread-safe.
class VolumeTexture {
 public:
  /// A grid texture from the scene's Texture (kind volume, `grid` set, 1 or 3 channels).
  VolumeTexture(std::shared_ptr<const VolumeGridFile> grid, const glm::dmat4& volume_to_world,
                TextureFilter filter, TextureWrap wrap);
  /// A constant: `value` (`one_channel`: value.x in every channel).
  VolumeTexture(glm::vec3 value, bool one_channel);

  /// The value at world point `p`.
  glm::vec3 eval(glm::vec3 p) const;
  /// Mitsuba's eval_1 at world point `p`.
  float eval_1(glm::vec3 p) const;
  /// Without a surface point (a lookup by (u, v) alone, which the loaders refuse for volume
  /// textures): the constant's value, 0 for a grid.
  glm::vec3 eval(glm::vec2 /*uv*/) const { return grid_ ? glm::vec3(0.0f) : constant_; }
  /// True for a grid, false for a constant.
  bool grid() const { return grid_ != nullptr; }

 private:
  /// The interpolated channels (channels_ of them, the rest 0) at world point p.
  glm::vec3 interpolate(glm::vec3 p) const;
  int wrap(float i, int n) const;
  glm::vec3 voxel(int x, int y, int z) const;

  std::shared_ptr<const VolumeGridFile> grid_;  ///< null: a constant
  glm::vec3 constant_{0.0f};
  int channels_ = 1;
  glm::vec3 to_local_[4];  ///< columns of the float affine map world -> [0, 1]^3
  glm::ivec3 resolution_{1, 1, 1};
  TextureFilter filter_ = TextureFilter::bilinear;
  TextureWrap wrap_ = TextureWrap::clamp;
};

}  // namespace tessera
