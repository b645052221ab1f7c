#include "camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "warp.h"

namespace tessera {

PerspectiveCamera::PerspectiveCamera(const Camera& c, int width, int height)
    : inv_width_(1.0f / float(width)),
      inv_height_(1.0f / float(height)),
      aperture_radius_(float(c.aperture_radius)),
      focus_distance_(float(c.focus_distance)) {
  const glm::dvec3 forward = glm::normalize(c.look_at - c.position);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, c.up));
  const glm::dvec3 up = glm::cross(right, forward);
  position_ = glm::vec3(c.position);
  forward_ = glm::vec3(forward);
  right_ = glm::vec3(right);
  up_ = glm::vec3(up);

  const double aspect = double(width) / double(height);
  const double tan_half = std::tan(c.fov_deg * 0.5 * 3.14159265358979323846 / 180.0);
  bool along_x = true;
  switch (c.fov_axis) {
    case FovAxis::x: along_x = true; break;
    case FovAxis::y: along_x = false; break;
    case FovAxis::smaller: along_x = width <= height; break;
    case FovAxis::larger: along_x = width >= height; break;
  }
  tan_half_x_ = float(along_x ? tan_half : tan_half * aspect);
  tan_half_y_ = float(along_x ? tan_half / aspect : tan_half);
}

Ray PerspectiveCamera::generate_ray(glm::vec2 film, glm::vec2 u_lens) const {
  const float sx = (2.0f * film.x * inv_width_ - 1.0f) * tan_half_x_;
  const float sy = (1.0f - 2.0f * film.y * inv_height_) * tan_half_y_;
  // Direction in camera space with forward at distance 1.
  glm::vec3 d_cam(sx, sy, 1.0f);
  glm::vec3 o_cam(0.0f);
  if (aperture_radius_ > 0) {
    const glm::vec2 lens = aperture_radius_ * square_to_concentric_disk(u_lens);
    const glm::vec3 focus = d_cam * focus_distance_;
    o_cam = glm::vec3(lens.x, lens.y, 0.0f);
    d_cam = focus - o_cam;
  }
  Ray ray;
  ray.o = position_ + o_cam.x * right_ + o_cam.y * up_;
  ray.d = glm::normalize(d_cam.x * right_ + d_cam.y * up_ + d_cam.z * forward_);
  return ray;
}

}  // namespace tessera
