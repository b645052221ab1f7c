// Reading an image header attribute (provenance) with OpenImageIO. Its own file: OIIO's headers
// and protobuf's disagree about byte-swap macros in one translation unit.
#pragma once

#include <filesystem>
#include <string>

namespace tessera::e2e {

/// The string attribute `name` of the image's header; empty when absent or unreadable.
std::string image_attribute(const std::filesystem::path& path, const std::string& name);

}  // namespace tessera::e2e
