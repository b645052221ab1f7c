// OpenImageIO's image checks (scene/image_check.h), reached through the image functions' table
// (image/image_io.h): linked in, or inside the image module.
#include "image/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "scene/scene_error.h"

namespace tessera {
namespace {

/// The first line of OpenImageIO's error text, or `fallback`.
std::string first_line(std::string text, const char* fallback) {
  text = text.substr(0, text.find('\n'));
  return text.empty() ? fallback : text;
}

const char* channel_name(const OIIO::ImageSpec& spec, int c, std::string& storage) {
  if (c < int(spec.channelnames.size()) && !spec.channelnames[c].empty()) {
    storage = spec.channelnames[c];
    return storage.c_str();
  }
  storage = std::to_string(c);
  return storage.c_str();
}

int band_rows(const OIIO::ImageSpec& spec) {
  const uint64_t row = uint64_t(spec.width) * uint64_t(spec.nchannels) * sizeof(float);
  return int(std::clamp<uint64_t>(kImageCheckBandBytes / row, 1, uint64_t(spec.height)));
}

/// `band` holds rows [y0, y0 + rows) of the image (0 = its top row).
void check_values(const std::string& path, const OIIO::ImageSpec& spec,
                  const std::vector<float>& band, size_t band_values, int y0) {
  const size_t channels = size_t(spec.nchannels);
  for (size_t i = 0; i < band_values; ++i) {
    const float v = band[i];
    if (std::isfinite(v) && v >= 0) continue;
    const size_t pixel = i / channels;
    std::string name;
    channel_name(spec, int(i % channels), name);
    const std::string what = std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "negative";
    throw SceneError(path + ": pixel (" + std::to_string(pixel % size_t(spec.width)) + ", " +
                     std::to_string(size_t(y0) + pixel / size_t(spec.width)) + ") channel " +
                     name + " is " + what + " (" + std::to_string(v) +
                     "); images must hold finite values >= 0");
  }
}

std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path,
                                             OIIO::Filesystem::IOMemReader& memory) {
  // With a proxy, OpenImageIO reads only `memory` (never the file system), and formats that
  // cannot read from one fail to open.
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, nullptr, &memory);
  if (!in) {
    throw SceneError(path + ": cannot be read as an image (" +
                     first_line(OIIO::geterror(), "unknown format") + ")");
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1) {
    throw SceneError(path + ": has no pixels (" + std::to_string(spec.width) + " x " +
                     std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                     " channels)");
  }
  return in;
}

}  // namespace

ImageHeader oiio_probe_image_bytes(const std::string& path, std::string_view bytes) {
  if (bytes.empty()) throw SceneError(path + ": empty file, not an image");
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  std::unique_ptr<OIIO::ImageInput> in = open_image(path, memory);
  const OIIO::ImageSpec& spec = in->spec();
  ImageHeader header;
  header.width = spec.width;
  header.height = spec.height;
  header.channels = spec.nchannels;
  header.bytes_per_value = int(spec.format.size());
  header.format = in->format_name();
  return header;
}

ImageCheck oiio_check_image_bytes(const std::string& path, std::string_view bytes,
                             uint64_t max_values) {
  if (bytes.empty()) throw SceneError(path + ": empty file, not an image");
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  std::unique_ptr<OIIO::ImageInput> in = open_image(path, memory);
  const OIIO::ImageSpec spec = in->spec();
  const uint64_t values = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels);
  if (values > max_values) {
    throw SceneError(path + ": " + std::to_string(spec.width) + " x " +
                     std::to_string(spec.height) + " x " + std::to_string(spec.nchannels) +
                     " values (at most " + std::to_string(max_values) + ")");
  }
  const int rows = band_rows(spec);
  std::vector<float> band(size_t(rows) * size_t(spec.width) * size_t(spec.nchannels));
  for (int y = 0; y < spec.height; y += rows) {
    const int n = std::min(rows, spec.height - y);
    if (!in->read_scanlines(0, 0, spec.y + y, spec.y + y + n, 0, 0, spec.nchannels,
                            OIIO::TypeDesc::FLOAT, band.data())) {
      throw SceneError(path + ": truncated or corrupt pixel data (" +
                       first_line(in->geterror(), "read failed") + ")");
    }
    check_values(path, spec, band, size_t(n) * size_t(spec.width) * size_t(spec.nchannels), y);
  }
  in->close();
  return {spec.width, spec.height, spec.nchannels, in->format_name()};
}

}  // namespace tessera
