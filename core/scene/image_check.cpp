#include "scene/image_check.h"

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

void check_values(const std::string& path, const OIIO::ImageSpec& spec,
                  const std::vector<float>& pixels) {
  size_t channels = size_t(spec.nchannels);
  for (size_t i = 0; i < pixels.size(); ++i) {
    float v = pixels[i];
    if (std::isfinite(v) && v >= 0) continue;
    size_t pixel = i / channels;
    std::string name;
    channel_name(spec, int(i % channels), name);
    std::string what = std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "negative";
    throw SceneError(path + ": pixel (" + std::to_string(pixel % size_t(spec.width)) + ", " +
                     std::to_string(pixel / size_t(spec.width)) + ") channel " + name + " is " +
                     what + " (" + std::to_string(v) +
                     "); images must hold finite values >= 0");
  }
}

}  // namespace

ImageCheck check_image_bytes(const std::string& path, std::string_view bytes) {
  if (bytes.empty()) throw SceneError(path + ": empty file, not an image");
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  // With a proxy, OpenImageIO reads only `memory` (never the file system), and formats that
  // cannot read from one fail to open.
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, nullptr, &memory);
  if (!in) {
    throw SceneError(path + ": cannot be read as an image (" +
                     first_line(OIIO::geterror(), "unknown format") + ")");
  }
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1) {
    throw SceneError(path + ": has no pixels (" + std::to_string(spec.width) + " x " +
                     std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                     " channels)");
  }
  uint64_t values = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels);
  if (values > kMaxImageValues) {
    throw SceneError(path + ": " + std::to_string(spec.width) + " x " +
                     std::to_string(spec.height) + " x " + std::to_string(spec.nchannels) +
                     " values (at most " + std::to_string(kMaxImageValues) + ")");
  }
  std::vector<float> pixels(values);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    throw SceneError(path + ": truncated or corrupt pixel data (" +
                     first_line(in->geterror(), "read failed") + ")");
  }
  in->close();
  check_values(path, spec, pixels);
  return {spec.width, spec.height, spec.nchannels, in->format_name()};
}

std::vector<std::string> scene_image_files(const Scene& scene) {
  std::vector<std::string> files;
  auto add = [&files](const std::string& file) {
    if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
  };
  for (const Texture& texture : scene.textures) {
    if (texture.kind == TextureKind::bitmap) add(texture.file);
  }
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::envmap) add(light.file);
  }
  return files;
}

}  // namespace tessera
