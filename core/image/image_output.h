// Writing rendered images with OpenImageIO.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace tessera {

/// A linear RGB float image, row-major, row 0 at the top.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< 3 floats per pixel
};

/// A channel written after R, G, B in EXR files (PNG has no room for it and leaves it out).
struct ExtraChannel {
  std::string name;           ///< e.g. "spp"
  std::vector<float> values;  ///< one per pixel, row-major like RgbImage
};

struct ImageWriteOptions {
  bool half = false;  ///< EXR only: half floats, values clamped to half's finite range
  /// EXR only: more channels (e.g. each pixel's samples for adaptive jobs). With `half` they
  /// are clamped like colours.
  std::vector<ExtraChannel> extra_channels;
  /// Provenance written as EXR header string attributes ("tessera:scene_sha256" ...) and as
  /// PNG text chunks.
  std::map<std::string, std::string> metadata;
};

/// Writes `image` to `path`; the format follows the extension: .exr (linear float32, or half on
/// request) or .png (8-bit sRGB, clamped to [0,1]). Throws std::runtime_error naming the file
/// and the reason on failure. NaN/Inf never reach a file: they are written as 0 (EXR half clamps).
void write_image(const RgbImage& image, const std::filesystem::path& path,
                 const ImageWriteOptions& options = {});

/// Encodes an image in memory as PNG (sRGB, 8 bit) or EXR (format "png" / "exr").
std::string encode_image(const RgbImage& image, const std::string& format,
                         const ImageWriteOptions& options = {});

/// Reads an image (any format OIIO knows) as linear RGB float (first three channels).
/// Throws std::runtime_error naming the file on failure.
RgbImage read_image(const std::filesystem::path& path);

/// Linear to sRGB transfer, for 8-bit output.
float linear_to_srgb(float linear);

}  // namespace tessera
