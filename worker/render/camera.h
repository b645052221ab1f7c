// The perspective camera with an optional thin lens.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "ray.h"
#include "scene/scene.h"

namespace tessera {

class PerspectiveCamera {
 public:
  /// Image of width x height pixels; the field of view spans the axis the scene names.
  PerspectiveCamera(const Camera& camera, int width, int height);

  /// The primary ray through film position `film` (in pixels: x to the right, y down, (0,0)
  /// the top-left corner of the image) using lens sample `u_lens` in [0,1)^2. The direction
  /// is unit length.
  Ray generate_ray(glm::vec2 film, glm::vec2 u_lens) const;

 private:
  glm::vec3 position_, right_, up_, forward_;
  float tan_half_x_, tan_half_y_;
  float inv_width_, inv_height_;
  float aperture_radius_, focus_distance_;
};

}  // namespace tessera
