// Mitsuba's `to_uv`: the affine map a texture applies to a surface point's (u, v) first.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

namespace tessera {

/// (u', v') = the first two rows of Texture::to_uv times (u, v, 1), evaluated in float as
/// Mitsuba's transform_affine is. to_uv is a glm matrix (to_uv[column][row]): its third column
/// is the translation.
struct UvTransform {
  float m00 = 1, m01 = 0, m02 = 0;  ///< u' = m00 u + m01 v + m02
  float m10 = 0, m11 = 1, m12 = 0;  ///< v' = m10 u + m11 v + m12

  static UvTransform from(const glm::dmat3& to_uv) {
    return {float(to_uv[0][0]), float(to_uv[1][0]), float(to_uv[2][0]),
            float(to_uv[0][1]), float(to_uv[1][1]), float(to_uv[2][1])};
  }

  glm::vec2 apply(glm::vec2 uv) const {
    return {m00 * uv.x + m01 * uv.y + m02, m10 * uv.x + m11 * uv.y + m12};
  }
};

}  // namespace tessera
