// The image module: OpenImageIO's code (oiio_image_io.cpp, oiio_image_check.cpp) built as a
// shared object that tessera-server and the tessera client embed and load at their first image
// (image_module_loader.cpp), so that neither maps OpenImageIO's ~250 libraries at start
// (tests/dashboard/start_libraries.sh checks it).
#pragma once

#include <cstdint>

#include "image/image_io.h"

namespace tessera {

/// Bumped with any change of ImageModule or ImageIo; the loader refuses a module of another
/// version.
inline constexpr uint32_t kImageModuleVersion = 5;

/// What the module exports: the image functions' table.
struct ImageModule {
  uint32_t version = kImageModuleVersion;
  const ImageIo* io = nullptr;
};

/// Loads the image module now (a no-op once loaded), so that the first image call does not
/// wait for OpenImageIO's libraries: tessera-server calls it on a thread of its own once it
/// listens. Throws std::runtime_error naming what failed; the next image call then tries again.
/// Defined where the module is loaded (image_module_loader.cpp), not where OpenImageIO is
/// linked in.
void load_image_module();

}  // namespace tessera

/// The module's one exported symbol (image_module_exports.cpp).
extern "C" const tessera::ImageModule* tessera_image_module();
