// Reading an image header attribute (provenance) with OpenImageIO. Its own file: OIIO's headers
// and protobuf's disagree about byte-swap macros in one translation unit.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tessera::e2e {

/// The string attribute `name` of the image's header; empty when absent or unreadable.
std::string image_attribute(const std::filesystem::path& path, const std::string& name);

/// The channel called `name` (e.g. "spp"), one float per pixel, row-major; empty when absent.
std::vector<float> image_channel(const std::filesystem::path& path, const std::string& name);

}  // namespace tessera::e2e
