#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// An orthonormal basis (s, t, n) around a unit normal n, built without branches on the
/// direction of n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
struct Frame {
  glm::vec3 s, t, n;

  explicit Frame(glm::vec3 normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
  }

  glm::vec3 to_world(glm::vec3 v) const { return v.x * s + v.y * t + v.z * n; }
  glm::vec3 to_local(glm::vec3 v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
};

}  // namespace tessera
