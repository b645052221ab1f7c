// image_check_memory (scene/image_check.h): from an image's header alone, without OpenImageIO,
// so that tessera-server can estimate a check before it loads the image module.
#include <algorithm>
#include <iterator>
#include <string_view>

#include "scene/image_check.h"

namespace tessera {
namespace {

/// What a decoder that reads a few rows at a time may hold besides them.
constexpr uint64_t kStreamedDecoderBytes = uint64_t(64) << 20;

}  // namespace

uint64_t image_check_memory(const ImageHeader& header) {
  const uint64_t row = uint64_t(header.width) * uint64_t(header.channels) * sizeof(float);
  const uint64_t band =
      std::max(row, std::min(kImageCheckBandBytes, row * uint64_t(header.height)));
  // OpenImageIO 2.4 reads these a few rows (or a row of tiles) at a time: checking 16384 x 8192
  // RGB images band by band peaked 45 MB above the file's bytes for float EXR (ZIP), 16 MB for
  // HDR, 17 MB for float TIFF and 10 MB for JPEG. Other decoders (PNG's for interlaced files
  // among them) may hold the whole image in its own pixel type.
  static constexpr std::string_view kStreamed[] = {"openexr", "hdr", "tiff", "jpeg"};
  const bool streamed = std::find(std::begin(kStreamed), std::end(kStreamed), header.format) !=
                        std::end(kStreamed);
  const uint64_t whole = header.values() * uint64_t(std::max(header.bytes_per_value, 1));
  const uint64_t decoder = streamed ? kStreamedDecoderBytes + 4 * row : whole;
  return decoder + band;
}

}  // namespace tessera
