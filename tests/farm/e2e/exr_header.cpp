#include "exr_header.h"

#include <OpenImageIO/imageio.h>

namespace tessera::e2e {

std::string image_attribute(const std::filesystem::path& path, const std::string& name) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return "";
  return std::string(in->spec().get_string_attribute(name));
}

}  // namespace tessera::e2e
