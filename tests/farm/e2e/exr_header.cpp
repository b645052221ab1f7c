#include "exr_header.h"

#include <OpenImageIO/imageio.h>

namespace tessera::e2e {

std::string image_attribute(const std::filesystem::path& path, const std::string& name) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return "";
  return std::string(in->spec().get_string_attribute(name));
}

std::vector<float> image_channel(const std::filesystem::path& path, const std::string& name) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  const int c = spec.channelindex(name);
  if (c < 0) return {};
  std::vector<float> out(size_t(spec.width) * size_t(spec.height));
  if (!in->read_image(0, 0, c, c + 1, OIIO::TypeDesc::FLOAT, out.data())) return {};
  return out;
}

}  // namespace tessera::e2e
