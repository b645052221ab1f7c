// The image module's one exported symbol (image_module.h); everything else in it is hidden.
#include "image/image_module.h"

extern "C" __attribute__((visibility("default"))) const tessera::ImageModule*
tessera_image_module() {
  static const tessera::ImageModule module{tessera::kImageModuleVersion, &tessera::oiio_image_io()};
  return &module;
}
