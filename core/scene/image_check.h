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

/// The most values (width x height x channels) an image file of a scene may hold, by default:
/// 2^29, a 16384 x 8192 RGBA map, so that a 16k environment map (16384 x 8192 RGB) is taken.
/// `tessera-worker render` and `tessera submit` check with it; tessera-server's
/// --max-texture-values may lower it (docs/security.md, "Limits").
inline constexpr uint64_t kMaxImageValues = uint64_t(16384) * 8192 * 4;

/// check_image_bytes decodes a band of rows of about this many bytes of floats at a time (at
/// least one row).
inline constexpr uint64_t kImageCheckBandBytes = uint64_t(8) << 20;

/// What an image's header says, read without decoding a pixel (probe_image_bytes).
struct ImageHeader {
  int width = 0;
  int height = 0;
  int channels = 0;
  int bytes_per_value = 0;  ///< of the file's pixel type: 1 for 8-bit PNG, 4 for float
  std::string format;       ///< OpenImageIO's format name
  uint64_t values() const { return uint64_t(width) * uint64_t(height) * uint64_t(channels); }
};

/// Reads the header of the image `bytes` of bundle path `path` (its extension chooses the
/// format, as OpenImageIO does for files), decoding no pixel. Throws SceneError("<path>: ...")
/// when it is not an image OpenImageIO can read or has no pixels.
ImageHeader probe_image_bytes(const std::string& path, std::string_view bytes);

/// The memory check_image_bytes may take for an image with `header`, besides its bytes: one band
/// of rows as floats (about 8 MiB) and the decoder's own: 64 MiB and four rows for the formats
/// whose decoder reads a few rows at a time (openexr, hdr, tiff, jpeg), the whole image in the
/// file's pixel type for the others (PNG's decoder holds an interlaced image whole).
uint64_t image_check_memory(const ImageHeader& header);

/// Decodes the image `bytes` of bundle path `path` in memory, header and every pixel of its
/// first subimage, as floats a band of rows at a time. Returns its size and format. Throws
/// SceneError("<path>: ...") when it is not an image OpenImageIO can read, is truncated or
/// corrupt, has no pixels, holds more than `max_values` values (checked from the header, before
/// any pixel is decoded), or has a NaN, infinite or negative value (naming the first such pixel
/// and channel).
ImageCheck check_image_bytes(const std::string& path, std::string_view bytes,
                             uint64_t max_values = kMaxImageValues);

/// The bundle paths of the images `scene` uses (bitmap textures, then envmap files), each once,
/// in order of first use: the files of Scene::referenced_files that check_image_bytes checks.
std::vector<std::string> scene_image_files(const Scene& scene);

}  // namespace tessera
