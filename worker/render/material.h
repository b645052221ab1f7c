#pragma once

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

/// A material as the integrator reads it.
struct RenderMaterial {
  MaterialType type = MaterialType::diffuse;
  glm::vec3 albedo{0.0f};  ///< diffuse reflectance
  float ior = 1.5f;        ///< glass: interior over exterior
  bool two_sided = false;  ///< diffuse and mirror: both sides reflect
};

}  // namespace tessera
