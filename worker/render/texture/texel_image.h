// Decoding a texture's image file into the texel values lookups interpolate.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace tessera {

/// A decoded texture image: linear values, row-major from the image's top row (Mitsuba's v = 0),
/// `channels` floats per texel.
struct TexelImage {
  int width = 0;
  int height = 0;
  int channels = 0;  ///< 1 (Y) or 3 (RGB)
  std::vector<float> texels;

  const float* texel(int x, int y) const {
    return texels.data() + (size_t(y) * size_t(width) + size_t(x)) * size_t(channels);
  }
};

/// Decodes the image file `file` (its bytes; any format OpenImageIO reads: PNG, JPEG, EXR, HDR,
/// TGA, BMP...) as Mitsuba's bitmap texture loads it:
///  - Y and YA images keep one channel, RGB and RGBA three; alpha is dropped unchanged (never
///    premultiplied); other channel counts are refused;
///  - 8- and 16-bit images are sRGB-decoded when `color_space` is srgb, divided by their
///    maximum code otherwise; 16-bit values are then rounded to half precision, as Mitsuba 3.9
///    stores them (it keeps 8-bit codes and decodes each texel to float when it fetches it);
///  - float images (EXR, HDR) are used as stored, whatever `color_space` says;
///  - an image narrower or lower than 2 texels is widened to 2 by repeating its column or row
///    (as Mitsuba 3.9 pads such images).
/// Throws SceneError("<origin>: <file>: ...") when the bytes cannot be decoded, the image has no
/// pixels or an unsupported channel count, or a texel is NaN, infinite or negative.
TexelImage decode_texel_image(const std::string& bytes, const std::string& file,
                              TextureColorSpace color_space, const std::string& origin);

}  // namespace tessera
