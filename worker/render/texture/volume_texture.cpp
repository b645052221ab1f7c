#include "volume_texture.h"

#include <algorithm>
#include <cmath>

#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "bitmap_texture.h"

namespace tessera {

VolumeTexture::VolumeTexture(std::shared_ptr<const VolumeGridFile> grid,
                             const glm::dmat4& volume_to_world, TextureFilter filter,
                             TextureWrap wrap)
    : grid_(std::move(grid)), channels_(int(grid_->channels)), filter_(filter), wrap_(wrap) {
  // Mitsuba inverts to_world in double (ScalarTransform4f holds float; the inverse of a float
  // matrix differs from this one in the last bits at most).
  const glm::dmat4 to_local = glm::inverse(volume_to_world);
  for (int c = 0; c < 4; ++c) to_local_[c] = glm::vec3(to_local[c]);
  resolution_ = glm::ivec3(grid_->resolution);
}

VolumeTexture::VolumeTexture(glm::vec3 value, bool one_channel)
    : constant_(one_channel ? glm::vec3(value.x) : value), channels_(one_channel ? 1 : 3) {
  for (int c = 0; c < 4; ++c) to_local_[c] = glm::vec3(0.0f);
}

int VolumeTexture::wrap(float i, int n) const {
  // i is an integer-valued float; reduced in double so that no far-away i overflows an int.
  const double d = i;
  if (wrap_ == TextureWrap::clamp) return int(std::clamp(d, 0.0, double(n - 1)));
  const double period = wrap_ == TextureWrap::mirror ? 2.0 * n : double(n);
  int k = std::clamp(int(d - period * std::floor(d / period)), 0, int(period) - 1);
  if (k >= n) k = 2 * n - 1 - k;  // mirror: the second half of a period runs backwards
  return k;
}

glm::vec3 VolumeTexture::voxel(int x, int y, int z) const {
  const size_t base = ((size_t(z) * size_t(resolution_.y) + size_t(y)) * size_t(resolution_.x) +
                       size_t(x)) *
                      size_t(channels_);
  const float* v = grid_->values.data() + base;
  return channels_ == 1 ? glm::vec3(v[0], 0.0f, 0.0f) : glm::vec3(v[0], v[1], v[2]);
}

glm::vec3 VolumeTexture::interpolate(glm::vec3 p) const {
  glm::vec3 q = to_local_[0] * p.x + to_local_[1] * p.y + to_local_[2] * p.z + to_local_[3];
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(q[k])) q[k] = 0.0f;
  }
  const glm::vec3 n(resolution_);
  if (filter_ == TextureFilter::nearest) {
    const glm::vec3 i = glm::floor(q * n);
    return voxel(wrap(i.x, resolution_.x), wrap(i.y, resolution_.y), wrap(i.z, resolution_.z));
  }
  const glm::vec3 pos = q * n - 0.5f;
  const glm::vec3 i0 = glm::floor(pos);
  const glm::vec3 w1 = pos - i0, w0 = 1.0f - w1;
  int x[2], y[2], z[2];
  for (int b = 0; b < 2; ++b) {
    x[b] = wrap(i0.x + float(b), resolution_.x);
    y[b] = wrap(i0.y + float(b), resolution_.y);
    z[b] = wrap(i0.z + float(b), resolution_.z);
  }
  // Dr.Jit's order: corners with x fastest, weight ((1 wx) wy) wz, summed one by one.
  glm::vec3 out(0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const int bx = corner & 1, by = (corner >> 1) & 1, bz = (corner >> 2) & 1;
    const float weight = (bx ? w1.x : w0.x) * (by ? w1.y : w0.y) * (bz ? w1.z : w0.z);
    out += voxel(x[bx], y[by], z[bz]) * weight;
  }
  return out;
}

glm::vec3 VolumeTexture::eval(glm::vec3 p) const {
  if (!grid_) return constant_;
  const glm::vec3 v = interpolate(p);
  return channels_ == 1 ? glm::vec3(v.x) : v;
}

float VolumeTexture::eval_1(glm::vec3 p) const {
  if (!grid_) {
    return channels_ == 1 ? constant_.x : (constant_.x + constant_.y + constant_.z) / 3.0f;
  }
  const glm::vec3 v = interpolate(p);
  return channels_ == 1 ? v.x : mitsuba_luminance(v);
}

}  // namespace tessera
