// Mitsuba's checkerboard texture.
#pragma once

#include <cmath>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "uv_transform.h"

namespace tessera {

/// Two colours alternating in squares of half a unit of (u, v) after to_uv (Mitsuba's
/// src/textures/checkerboard.cpp): color0 where the fractional parts of u and v are both
/// > 1/2 or both <= 1/2, color1 elsewhere. Immutable: thread-safe.
///
/// Mitsuba's eval_1 (the scalar lookup: roughness, opacity) picks the colours the other way
/// round than its eval (color1 where eval gives color0; Mitsuba 3.9.1 does so). Tessera follows
/// it, so that a published scene whose roughness is a checkerboard renders as in Mitsuba.
class Checkerboard {
 public:
  Checkerboard(glm::vec3 color0, glm::vec3 color1, UvTransform to_uv)
      : color0_(color0), color1_(color1), to_uv_(to_uv) {}

  glm::vec3 eval(glm::vec2 uv) const {
    const glm::vec2 p = to_uv_.apply(uv);
    const bool high_u = p.x - std::floor(p.x) > 0.5f, high_v = p.y - std::floor(p.y) > 0.5f;
    return high_u == high_v ? color0_ : color1_;
  }
  /// The colour the scalar lookup reads (Mitsuba's eval_1 order, see above).
  glm::vec3 eval_scalar_order(glm::vec2 uv) const {
    const glm::vec2 p = to_uv_.apply(uv);
    const bool high_u = p.x - std::floor(p.x) > 0.5f, high_v = p.y - std::floor(p.y) > 0.5f;
    return high_u != high_v ? color0_ : color1_;
  }

 private:
  glm::vec3 color0_, color1_;
  UvTransform to_uv_;
};

}  // namespace tessera
