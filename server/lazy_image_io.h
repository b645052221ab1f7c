// tessera-server's image module (server/lazy_image_io.cpp): core's OpenImageIO code, loaded at
// the first image call, or by load_image_module() once the server listens.
#pragma once

namespace tessera::server {

/// Loads the image module now (a no-op once loaded), so that the first preview, output or
/// texture check does not wait for OpenImageIO's libraries (0.6 s of CPU at load 10). main
/// calls it on a thread of its own after both listeners are up. Throws std::runtime_error
/// naming what failed; the next image call then tries again.
void load_image_module();

}  // namespace tessera::server
