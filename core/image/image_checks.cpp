// The image checks of scene/image_check.h: each the one body that every executable runs, calling
// OpenImageIO's through the image functions' table (image_io.h), linked in or in the module.
#include "image/image_io.h"
#include "scene/image_check.h"

namespace tessera {

ImageHeader probe_image_bytes(const std::string& path, std::string_view bytes) {
  return image_io().probe_image_bytes(path, bytes);
}

ImageCheck check_image_bytes(const std::string& path, std::string_view bytes, uint64_t max_values) {
  return image_io().check_image_bytes(path, bytes, max_values);
}

}  // namespace tessera
