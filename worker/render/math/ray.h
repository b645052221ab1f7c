#pragma once

#include <limits>

#include <glm/vec3.hpp>

namespace tessera {

/// A ray o + t d for t in [0, t_max]. d need not be unit length.
struct Ray {
  glm::vec3 o;
  glm::vec3 d;
  float t_max = std::numeric_limits<float>::infinity();
};

}  // namespace tessera
