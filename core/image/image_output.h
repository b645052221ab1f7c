// Writing and reading images: EXR and PNG files, or their bytes in memory. OpenImageIO does the
// work (oiio_image_io.cpp), reached through image_io.h.
#pragma once

#include <cmath>
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

/// One image file written band by band, top to bottom, so that only a band of rows is in memory
/// at a time: the server writes a job's EXR and PNG a row of tiles at a time (an 8192 x 8192 image
/// is 805 MB as float RGB; BENCHMARKS.md, "Server memory on the largest image").
/// The file is byte for byte the one write_image gives for the whole image (write_image is this
/// stream with one band). It is written to a hidden temporary name beside `path`; finish()
/// closes, syncs and renames it into place; a stream destroyed unfinished (an exception on the
/// way) removes its temporary file. Throws std::runtime_error naming the file and the reason.
class ImageFileStream {
 public:
  /// The format follows the extension, as write_image's. The EXR's extra channels are
  /// `options.extra_channels`' names (their values are not read: each band brings its own).
  ImageFileStream(const std::filesystem::path& path, int width, int height, const ImageWriteOptions& options);
  ImageFileStream(ImageFileStream&& other) noexcept;
  ImageFileStream& operator=(ImageFileStream&& other) noexcept;
  ImageFileStream(const ImageFileStream&) = delete;
  ImageFileStream& operator=(const ImageFileStream&) = delete;
  ~ImageFileStream();

  /// The next band.height rows (band.width must be the image's width). `extra`: the band's
  /// values of each extra channel, in their order (ignored for PNG).
  void write_rows(const RgbImage& band, const std::vector<ExtraChannel>& extra = {});
  /// Every row written: the file goes into place (an in-memory stream keeps its bytes).
  void finish();

  /// A stream that encodes into memory instead (format "exr" or "png", as encode_image): what
  /// take_bytes() hands over after finish().
  static ImageFileStream in_memory(const std::string& format, int width, int height,
                                   const ImageWriteOptions& options);
  /// The encoded file of a finished in-memory stream (empty for a file).
  std::string take_bytes();

  struct State;  ///< opaque: the implementation's own stream (image_io.h)

 private:
  ImageFileStream() = default;
  State* state_ = nullptr;  ///< owned; null once finished
  std::string bytes_;
};

/// Encodes an image in memory as PNG (sRGB, 8 bit) or EXR (format "png" / "exr"): an in-memory
/// ImageFileStream with one band.
std::string encode_image(const RgbImage& image, const std::string& format,
                         const ImageWriteOptions& options = {});

/// Reads an image (any format OIIO knows) as linear RGB float (first three channels).
/// Throws std::runtime_error naming the file on failure.
RgbImage read_image(const std::filesystem::path& path);

/// Linear to sRGB transfer (IEC 61966-2-1), for 8-bit output: in double, so the 8-bit rounding
/// that follows is not disturbed by float error.
inline float linear_to_srgb(float linear) {
  const double l = linear;
  return float(l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055);
}

}  // namespace tessera
