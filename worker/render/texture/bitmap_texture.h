// Mitsuba's bitmap texture: an image looked up by (u, v) with nearest or bilinear filtering.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"
#include "texel_image.h"
#include "uv_transform.h"

namespace tessera {

/// Lookups into a decoded image exactly as Mitsuba 3's bitmap texture (src/textures/bitmap.cpp,
/// over Dr.Jit's Texture) makes them, at zero footprint: Mitsuba has no ray differentials, so it
/// never filters over a footprint or uses mip levels, and neither does this.
///
/// Conventions: (u, v) first goes through to_uv; then u runs along the image's columns and v
/// along its rows from the top row (no flip: v = 0 is the first row of the file, and texel
/// (x, y) covers [x, x+1)/width x [y, y+1)/height). Bilinear interpolates between texel centres
/// at (u width - 1/2, v height - 1/2); nearest takes the texel containing (u width, v height).
/// Texel indices outside the image wrap: repeat (modulo), mirror (reflected every other
/// period), clamp (edge texel).
///
/// Float arithmetic as Mitsuba's, so the results agree with it to rounding (Mitsuba fuses
/// multiply-adds, Tessera does not). Non-finite (u, v) read as (0, 0). Immutable: thread-safe.
class BitmapTexture {
 public:
  BitmapTexture(TexelImage image, TextureFilter filter, TextureWrap wrap, UvTransform to_uv);

  /// The texel value at (u, v); one-channel images give (y, y, y).
  glm::vec3 eval(glm::vec2 uv) const;
  /// Mitsuba's eval_1: the single channel, or the luminance (Rec. 709) of the RGB value.
  float eval_1(glm::vec2 uv) const;
  /// d eval_1 / du and d eval_1 / dv (Mitsuba's eval_1_grad): the derivative of the bilinear
  /// interpolant of the texels' eval_1 values, through to_uv; zero for nearest filtering
  /// (piecewise constant). Mitsuba scales both partials of a rotated to_uv by the width and
  /// the height the wrong way round when they differ; this uses the chain rule as it is.
  glm::vec2 gradient(glm::vec2 uv) const;

  int width() const { return image_.width; }
  int height() const { return image_.height; }
  int channels() const { return image_.channels; }

 private:
  struct Footprint {  ///< the four texels around a bilinear lookup and their weights
    int x0, x1, y0, y1;
    float wx1, wy1;  ///< weights of x1 and y1; x0 and y0 get 1 - these
  };
  Footprint bilinear_footprint(glm::vec2 uv_image) const;
  int wrap(int i, int resolution) const;
  glm::vec3 texel(int x, int y) const;
  float texel_1(int x, int y) const;

  TexelImage image_;
  TextureFilter filter_;
  TextureWrap wrap_;
  UvTransform to_uv_;
};

/// Luminance of linear Rec. 709 RGB with Mitsuba's coefficients (its eval_1 of RGB textures).
inline float mitsuba_luminance(glm::vec3 c) {
  return c.x * 0.212671f + c.y * 0.715160f + c.z * 0.072169f;
}

}  // namespace tessera
