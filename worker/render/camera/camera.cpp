#include "render/camera/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/sampling/warp.h"

namespace tessera {

ProjectiveCamera::ProjectiveCamera(const Camera& c, int width, int height)
    : projection_(c.projection),
      inv_width_(1.0f / float(width)),
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

  if (c.projection == Projection::orthographic) {
    half_x_ = float(0.5 * c.view_size.x);
    // A view that follows the image's aspect (a Mitsuba sensor's) keeps its width at another
    // aspect; at its own, view_aspect / aspect is exactly 1.
    const double aspect = double(width) / double(height);
    half_y_ = float(c.view_aspect > 0 ? 0.5 * c.view_size.y * (c.view_aspect / aspect) : 0.5 * c.view_size.y);
    aperture_radius_ = 0;
    return;
  }
  // The view's half extents at distance 1 for this image's aspect (a diagonal field of view,
  // Mitsuba's focal_length, becomes the horizontal one for it, as Mitsuba does at its film's).
  const glm::dvec2 half = fov_half_tangents(c.fov_deg, c.fov_axis, double(width) / double(height));
  half_x_ = float(half.x);
  half_y_ = float(half.y);
}

Ray ProjectiveCamera::generate_ray(glm::vec2 film, glm::vec2 u_lens) const {
  const float sx = (2.0f * film.x * inv_width_ - 1.0f) * half_x_;
  const float sy = (1.0f - 2.0f * film.y * inv_height_) * half_y_;
  Ray ray;
  if (projection_ == Projection::orthographic) {
    ray.o = position_ + sx * right_ + sy * up_;
    ray.d = forward_;
    return ray;
  }
  // Direction in camera space with forward at distance 1.
  glm::vec3 d_cam(sx, sy, 1.0f);
  glm::vec3 o_cam(0.0f);
  if (aperture_radius_ > 0) {
    const glm::vec2 lens = aperture_radius_ * square_to_concentric_disk(u_lens);
    const glm::vec3 focus = d_cam * focus_distance_;
    o_cam = glm::vec3(lens.x, lens.y, 0.0f);
    d_cam = focus - o_cam;
  }
  ray.o = position_ + o_cam.x * right_ + o_cam.y * up_;
  ray.d = glm::normalize(d_cam.x * right_ + d_cam.y * up_ + d_cam.z * forward_);
  return ray;
}

}  // namespace tessera
