// Checking an image file of a bundle (a bitmap texture, an environment map) before a job is
// accepted, so that a broken image is refused at submit with its name rather than met by every
// worker mid-render.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace tessera {

/// What check_image_bytes found.
struct ImageCheck {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::string format;  ///< OpenImageIO's format name: "openexr", "png", "hdr", "jpeg", ...
};

/// The most values (width x height x channels) an image may hold: 2^28 (a 16k x 16k RGBA map).
inline constexpr uint64_t kMaxImageValues = uint64_t(1) << 28;

/// Decodes the image `bytes` of bundle path `path` (its extension chooses the format, as
/// OpenImageIO does for files) entirely in memory, header and every pixel of its first
/// subimage, as floats. Returns its size and format. Throws SceneError("<path>: ...") when it
/// is not an image OpenImageIO can read, is truncated or corrupt, has no pixels, holds more
/// than kMaxImageValues values, or has a NaN, infinite or negative value (naming the first such
/// pixel and channel).
ImageCheck check_image_bytes(const std::string& path, std::string_view bytes);

/// The bundle paths of the images `scene` uses (bitmap textures, then envmap files), each once,
/// in order of first use: the files of Scene::referenced_files that check_image_bytes checks.
std::vector<std::string> scene_image_files(const Scene& scene);

}  // namespace tessera
