#include "bitmap_texture.h"

#include <cmath>
#include <utility>

namespace tessera {
namespace {

/// floor() as an int, for image positions. Positions beyond +-2^30 texels (where float has no
/// fraction left anyway) are clamped so that the conversion stays defined; NaN reads as 0.
int floor_to_int(float x) {
  if (!(x == x)) return 0;
  constexpr float kLimit = 1073741824.0f;  // 2^30
  return int(std::floor(std::fmin(std::fmax(x, -kLimit), kLimit)));
}

glm::vec2 finite_or_zero(glm::vec2 uv) {
  return {std::isfinite(uv.x) ? uv.x : 0.0f, std::isfinite(uv.y) ? uv.y : 0.0f};
}

}  // namespace

BitmapTexture::BitmapTexture(TexelImage image, TextureFilter filter, TextureWrap wrap,
                             UvTransform to_uv)
    : image_(std::move(image)), filter_(filter), wrap_(wrap), to_uv_(to_uv) {}

int BitmapTexture::wrap(int i, int resolution) const {
  if (wrap_ == TextureWrap::clamp) return i < 0 ? 0 : (i >= resolution ? resolution - 1 : i);
  // Dr.Jit's definition: the period index `div` rounds toward zero after shifting negative
  // positions by one, the remainder is made non-negative, and mirror flips the periods whose
  // parity differs from the first one's.
  const int div = (i < 0 ? i + 1 : i) / resolution;
  int mod = i - div * resolution;
  if (mod < 0) mod += resolution;
  if (wrap_ == TextureWrap::mirror && !(((div & 1) == 0) != (i < 0))) mod = resolution - 1 - mod;
  return mod;
}

glm::vec3 BitmapTexture::texel(int x, int y) const {
  const float* t = image_.texel(x, y);
  return image_.channels == 1 ? glm::vec3(t[0]) : glm::vec3(t[0], t[1], t[2]);
}

float BitmapTexture::texel_1(int x, int y) const {
  const float* t = image_.texel(x, y);
  return image_.channels == 1 ? t[0] : mitsuba_luminance({t[0], t[1], t[2]});
}

BitmapTexture::Footprint BitmapTexture::bilinear_footprint(glm::vec2 uv_image) const {
  const float px = uv_image.x * float(image_.width) - 0.5f;
  const float py = uv_image.y * float(image_.height) - 0.5f;
  const int ix = floor_to_int(px), iy = floor_to_int(py);
  return {wrap(ix, image_.width),  wrap(ix + 1, image_.width),
          wrap(iy, image_.height), wrap(iy + 1, image_.height),
          px - float(ix),          py - float(iy)};
}

glm::vec3 BitmapTexture::eval(glm::vec2 uv) const {
  const glm::vec2 p = to_uv_.apply(finite_or_zero(uv));
  if (filter_ == TextureFilter::nearest) {
    return texel(wrap(floor_to_int(p.x * float(image_.width)), image_.width),
                 wrap(floor_to_int(p.y * float(image_.height)), image_.height));
  }
  const Footprint f = bilinear_footprint(p);
  const float wx0 = 1.0f - f.wx1, wy0 = 1.0f - f.wy1;
  // Corner order and weight products as Dr.Jit's: (x0,y0), (x1,y0), (x0,y1), (x1,y1).
  glm::vec3 sum = texel(f.x0, f.y0) * (wx0 * wy0);
  sum += texel(f.x1, f.y0) * (f.wx1 * wy0);
  sum += texel(f.x0, f.y1) * (wx0 * f.wy1);
  sum += texel(f.x1, f.y1) * (f.wx1 * f.wy1);
  return sum;
}

float BitmapTexture::eval_1(glm::vec2 uv) const {
  const glm::vec3 c = eval(uv);
  return image_.channels == 1 ? c.x : mitsuba_luminance(c);
}

glm::vec2 BitmapTexture::gradient(glm::vec2 uv) const {
  if (filter_ == TextureFilter::nearest) return {0.0f, 0.0f};
  const Footprint f = bilinear_footprint(to_uv_.apply(finite_or_zero(uv)));
  const float f00 = texel_1(f.x0, f.y0), f10 = texel_1(f.x1, f.y0);
  const float f01 = texel_1(f.x0, f.y1), f11 = texel_1(f.x1, f.y1);
  const float wx0 = 1.0f - f.wx1, wy0 = 1.0f - f.wy1;
  // Partials with respect to the image position (texels), then through
  // position = to_uv(uv) * resolution - 1/2.
  const float dfdx = wy0 * (f10 - f00) + f.wy1 * (f11 - f01);
  const float dfdy = wx0 * (f01 - f00) + f.wx1 * (f11 - f10);
  const float gx = dfdx * float(image_.width), gy = dfdy * float(image_.height);
  return {gx * to_uv_.m00 + gy * to_uv_.m10, gx * to_uv_.m01 + gy * to_uv_.m11};
}

}  // namespace tessera
