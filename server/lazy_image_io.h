// tessera-server loads its image module (core/image/image_module.h) on a thread once it
// listens, so that the first preview, output or texture check does not wait for OpenImageIO.
#pragma once

#include "image/image_module.h"

namespace tessera::server {

using tessera::load_image_module;

}  // namespace tessera::server
