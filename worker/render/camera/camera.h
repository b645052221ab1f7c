// The camera: a perspective pinhole with an optional thin lens, or an orthographic projection.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/math/ray.h"
#include "scene/scene.h"

namespace tessera {

/// The scene's Camera made ready to generate rays (Mitsuba's two projective cameras).
class ProjectiveCamera {
 public:
  /// Image of width x height pixels. Perspective: the field of view spans the axis the scene
  /// names. Orthographic: the image covers camera.view_size around camera.position.
  ProjectiveCamera(const Camera& camera, int width, int height);

  /// The primary ray through film position `film` (in pixels: x to the right, y down, (0,0)
  /// the top-left corner of the image) using lens sample `u_lens` in [0,1)^2 (unused by a
  /// pinhole and by the orthographic camera). The direction is unit length. Orthographic rays
  /// all have the view direction and start on the view rectangle.
  Ray generate_ray(glm::vec2 film, glm::vec2 u_lens) const;

  /// Whether generate_ray reads u_lens: a perspective camera with a thin lens (aperture > 0).
  bool uses_lens() const { return projection_ != Projection::orthographic && aperture_radius_ > 0; }

 private:
  Projection projection_;
  glm::vec3 position_, right_, up_, forward_;
  /// perspective: tangents of the half fields of view; orthographic: half the view size.
  float half_x_, half_y_;
  float inv_width_, inv_height_;
  float aperture_radius_, focus_distance_;
};

}  // namespace tessera
