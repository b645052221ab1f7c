#include "texel_image.h"

#include <cmath>
#include <memory>

#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "scene/scene_error.h"
#include "srgb.h"

namespace tessera {
namespace {

[[noreturn]] void fail(const std::string& origin, const std::string& file,
                       const std::string& what) {
  throw SceneError(origin + ": " + file + ": " + what);
}

/// 8- and 16-bit codes: the images Mitsuba sRGB-decodes (unless raw) and stores as half.
bool is_integer(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::UINT8 || t.basetype == OIIO::TypeDesc::UINT16;
}

/// The widest channel format of the file (files may store channels in different formats).
OIIO::TypeDesc storage_format(const OIIO::ImageSpec& spec) {
  OIIO::TypeDesc widest = spec.format;
  for (const OIIO::TypeDesc& t : spec.channelformats) {
    if (t.size() > widest.size()) widest = t;
  }
  return widest;
}

/// Where each channel of the decoded texel comes from: Y/YA -> {0}, RGB/RGBA -> {0, 1, 2}.
int kept_channels(int file_channels) {
  switch (file_channels) {
    case 1:
    case 2:
      return 1;
    case 3:
    case 4:
      return 3;
    default:
      return 0;
  }
}

void check_values(const TexelImage& image, const std::string& origin, const std::string& file) {
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) {
        const float v = image.texel(x, y)[c];
        if (std::isfinite(v) && v >= 0) continue;
        const char* what = std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "negative";
        fail(origin, file,
             "texel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                 std::to_string(c) + " is " + what + "; texture values must be finite and >= 0");
      }
    }
  }
}

/// Repeats the only column and/or row of an image narrower or lower than 2 texels.
TexelImage widen_to_2x2(const TexelImage& image) {
  if (image.width >= 2 && image.height >= 2) return image;
  TexelImage out;
  out.width = std::max(image.width, 2);
  out.height = std::max(image.height, 2);
  out.channels = image.channels;
  out.texels.resize(size_t(out.width) * size_t(out.height) * size_t(out.channels));
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      const float* src = image.texel(std::min(x, image.width - 1), std::min(y, image.height - 1));
      float* dst =
          out.texels.data() + (size_t(y) * size_t(out.width) + size_t(x)) * size_t(out.channels);
      for (int c = 0; c < out.channels; ++c) dst[c] = src[c];
    }
  }
  return out;
}

}  // namespace

TexelImage decode_texel_image(const std::string& bytes, const std::string& file,
                              TextureColorSpace color_space, const std::string& origin) {
  // The bytes are in memory (a job's bundle); OpenImageIO reads them through a memory proxy.
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  OIIO::ImageSpec config;
  // Keep colour and alpha as stored: OpenImageIO would otherwise premultiply PNG colours by
  // their alpha, which Mitsuba never does.
  config.attribute("oiio:UnassociatedAlpha", 1);
  // Readers take the proxy from the configuration (passing it to open() alone is not enough
  // in OpenImageIO 2.4 once a configuration is given).
  OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file, &config, &proxy);
  if (!in) fail(origin, file, "cannot decode image: " + OIIO::geterror());

  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) {
    fail(origin, file,
         "the image has no pixels (" + std::to_string(spec.width) + "x" +
             std::to_string(spec.height) + ")");
  }
  const int kept = kept_channels(spec.nchannels);
  if (kept == 0) {
    fail(origin, file,
         "unsupported channel count " + std::to_string(spec.nchannels) +
             " (expected Y, YA, RGB or RGBA)");
  }
  const OIIO::TypeDesc format = storage_format(spec);
  // Integer images of up to 16 bits are read as 16-bit codes (OpenImageIO widens 8-bit code k
  // to 257 k exactly), so that code / 65535 is the exact fraction Mitsuba converts.
  const bool integer = is_integer(format);
  const size_t values = size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels);
  std::vector<uint16_t> codes(integer ? values : 0);
  std::vector<float> floats(integer ? 0 : values);
  const bool read =
      integer ? in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT16, codes.data())
              : in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, floats.data());
  if (!read) fail(origin, file, "cannot decode image: " + in->geterror());

  const bool decode_srgb = integer && color_space == TextureColorSpace::srgb;
  // Mitsuba 3.9 keeps 8-bit codes (decoding them to float at each fetch) and stores 16-bit
  // images in half precision (measured with worker/render/texture/mitsuba_reference.py).
  const bool to_half =
      format.basetype == OIIO::TypeDesc::UINT16 || format.basetype == OIIO::TypeDesc::HALF;

  TexelImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = kept;
  image.texels.resize(size_t(spec.width) * size_t(spec.height) * size_t(kept));
  for (size_t p = 0; p < size_t(spec.width) * size_t(spec.height); ++p) {
    for (int c = 0; c < kept; ++c) {
      const size_t i = p * size_t(spec.nchannels) + size_t(c);
      float f = 0;
      if (integer) {
        const double v = double(codes[i]) / 65535.0;
        f = float(decode_srgb ? srgb_to_linear(v) : v);
      } else {
        f = floats[i];
      }
      if (to_half && std::isfinite(f)) f = float(Imath::half(f));
      image.texels[p * size_t(kept) + size_t(c)] = f;
    }
  }
  check_values(image, origin, file);
  return widen_to_2x2(image);
}

}  // namespace tessera
