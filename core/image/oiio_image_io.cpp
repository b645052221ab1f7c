// Image files through OpenImageIO: EXR (linear float32 or half) and PNG (8-bit sRGB). The one
// body of the image functions (image/image_io.h): each executable reaches it through
// image_io(), linked in (linked_image_io.cpp) or in the image module (image_module.h).
//
// Every value is sanitised here, before OIIO sees it, so that the bits in a file do not depend
// on how an OIIO version converts NaN, Inf or out-of-range values: NaN/Inf become 0, half output
// is clamped to half's finite range, PNG output is clamped to [0, 1] and quantised with
// round-to-nearest (no dithering: the same image always gives the same bytes).
#include "image/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>

namespace tessera {
namespace {

enum class FileFormat { kExr, kPng };

constexpr const char* kSupportedExtensions = ".exr, .png";
constexpr float kHalfMax = 65504.0f;  // largest finite half
/// zlib's level for PNG (OIIO's default is 6). The server writes a PNG beside every job's EXR:
/// at 6 that PNG cost 61 ms of CPU for a 512x512 Cornell box (254 KB), at 1 it costs 12 ms
/// (297 KB, +17 %): the PNG is the preview of a linear EXR, not an archive (BENCHMARKS.md,
/// "What a result and a job cost the server, counted"). Lossless either way.
constexpr int kPngZlibLevel = 1;

/// "exr", ".EXR" -> kExr; anything else -> nullopt.
std::optional<FileFormat> format_from_extension(std::string_view ext) {
  if (!ext.empty() && ext.front() == '.') ext.remove_prefix(1);
  std::string lower(ext);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (lower == "exr") return FileFormat::kExr;
  if (lower == "png") return FileFormat::kPng;
  return std::nullopt;
}

const char* oiio_format_name(FileFormat format) {
  return format == FileFormat::kExr ? "openexr" : "png";
}

void check_dimensions(const RgbImage& image, const std::string& what) {
  if (image.width <= 0 || image.height <= 0) {
    throw std::runtime_error(what + ": image has no pixels (" + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + ")");
  }
  const size_t expected = size_t(image.width) * size_t(image.height) * 3;
  if (image.rgb.size() != expected) {
    throw std::runtime_error(what + ": image holds " + std::to_string(image.rgb.size()) +
                             " floats, " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + " RGB needs " +
                             std::to_string(expected));
  }
}

float finite_or_zero(float v) { return std::isfinite(v) ? v : 0.0f; }

/// What OIIO is handed: the file's spec and sanitised pixels (float for EXR, uint8 for PNG).
struct PreparedImage {
  OIIO::ImageSpec spec;
  std::vector<float> f32;
  std::vector<uint8_t> u8;

  OIIO::TypeDesc data_type() const {
    return u8.empty() ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  }
  const void* data() const {
    return u8.empty() ? static_cast<const void*>(f32.data()) : static_cast<const void*>(u8.data());
  }
};

/// The file's spec for a `width` x `height` image: EXR float32 (or half) R, G, B and the extra
/// channels' names, or PNG 8-bit sRGB; the metadata as attributes.
OIIO::ImageSpec file_spec(int width, int height, FileFormat format, const ImageWriteOptions& options) {
  OIIO::ImageSpec spec;
  if (format == FileFormat::kExr) {
    const OIIO::TypeDesc file_type = options.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
    spec = OIIO::ImageSpec(width, height, 3 + int(options.extra_channels.size()), file_type);
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.channelnames = {"R", "G", "B"};
    for (const ExtraChannel& extra : options.extra_channels) spec.channelnames.push_back(extra.name);
  } else {
    spec = OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("png:compressionLevel", kPngZlibLevel);
  }
  for (const auto& [key, value] : options.metadata) spec.attribute(key, value);
  return spec;
}

/// Rows of `image` (all of it, or a band of a larger one) sanitised for `format` into `out`'s
/// f32 or u8: EXR interleaves R, G, B and `extra`'s values (one per pixel of `image` each, in
/// the spec's channel order), NaN/Inf as 0, clamped to half's range for half; PNG clamps to
/// [0, 1], encodes sRGB and rounds to 8 bits.
void convert_pixels(const RgbImage& image, FileFormat format, bool half, const std::vector<ExtraChannel>& extra,
                    PreparedImage* out) {
  const size_t pixels = size_t(image.width) * size_t(image.height);
  if (format == FileFormat::kExr) {
    const int channels = 3 + int(extra.size());
    for (const ExtraChannel& e : extra) {
      if (e.values.size() != pixels) {
        throw std::runtime_error("extra channel " + e.name + " holds " + std::to_string(e.values.size()) +
                                 " values for " + std::to_string(pixels) + " pixels");
      }
    }
    out->f32.resize(pixels * size_t(channels));
    for (size_t p = 0; p < pixels; ++p) {
      for (int c = 0; c < channels; ++c) {
        float v = finite_or_zero(c < 3 ? image.rgb[p * 3 + size_t(c)] : extra[size_t(c - 3)].values[p]);
        // Half's conversion turns anything above 65519.99 into Inf: clamp first.
        if (half) v = std::clamp(v, -kHalfMax, kHalfMax);
        out->f32[p * size_t(channels) + size_t(c)] = v;
      }
    }
  } else {
    out->u8.resize(image.rgb.size());
    for (size_t i = 0; i < image.rgb.size(); ++i) {
      const float v = std::clamp(finite_or_zero(image.rgb[i]), 0.0f, 1.0f);
      out->u8[i] = uint8_t(std::lround(linear_to_srgb(v) * 255.0f));
    }
  }
}

/// Creates an ImageOutput for `format`, optionally bound to an in-memory proxy.
std::unique_ptr<OIIO::ImageOutput> create_output(FileFormat format, const std::string& what,
                                                 OIIO::Filesystem::IOProxy* proxy) {
  auto out = OIIO::ImageOutput::create(oiio_format_name(format), proxy);
  if (!out) {
    throw std::runtime_error(what + ": OpenImageIO has no " + oiio_format_name(format) +
                             " writer: " + OIIO::geterror());
  }
  if (proxy != nullptr && !out->supports("ioproxy")) {
    throw std::runtime_error(what + ": the OpenImageIO " + oiio_format_name(format) +
                             " writer cannot write to memory");
  }
  return out;
}

/// A temporary file beside the destination, removed unless released after a successful rename.
class TempFile {
 public:
  explicit TempFile(const std::filesystem::path& destination) {
    std::random_device random;
    const uint64_t nonce = (uint64_t(random()) << 32) ^ random();
    char suffix[40];
    std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%016llx", long(::getpid()),
                  static_cast<unsigned long long>(nonce));
    // Hidden, and keeping the extension last so that nothing mistakes it for a finished image.
    path_ = destination.parent_path() /
            ("." + destination.filename().string() + suffix + destination.extension().string());
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (!released_) {
      std::error_code ignored;
      std::filesystem::remove(path_, ignored);
    }
  }
  const std::filesystem::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  bool released_ = false;
};

/// Flushes a file (or folder) to stable storage, so that a rename cannot outlive its content
/// across a power loss. Throws on failure when `required`.
void fsync_path(const std::filesystem::path& path, bool required, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (required)
      throw std::runtime_error(what + ": cannot reopen to sync: " + std::strerror(errno));
    return;
  }
  const bool ok = ::fsync(fd) == 0;
  const int sync_errno = errno;
  ::close(fd);
  if (!ok && required) {
    throw std::runtime_error(what + ": fsync failed: " + std::strerror(sync_errno));
  }
}

/// sRGB to linear, the inverse of linear_to_srgb.
float srgb_to_linear(float srgb) {
  const double s = srgb;
  return float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

/// Whether pixels read from a file with `spec` are sRGB-encoded: as the file says, or, when it
/// says nothing, when its samples are integers (8/16-bit PNG, JPEG... are sRGB by convention).
bool is_srgb_encoded(const OIIO::ImageSpec& spec) {
  const std::string colorspace = spec.get_string_attribute("oiio:ColorSpace");
  if (!colorspace.empty()) return OIIO::Strutil::iequals(colorspace, "sRGB");
  return !spec.format.is_floating_point();
}

/// An image being written band by band: to a temporary file beside `path`, or into `memory`;
/// OIIO's writer and the rows so far. Members go in reverse order: the writer is closed into its
/// file or memory before the temporary file is removed (an unfinished stream) or memory freed.
struct OiioStream {
  std::filesystem::path path;  ///< empty for an in-memory stream
  std::string what;
  FileFormat format = FileFormat::kExr;
  int width = 0, height = 0;
  bool half = false;
  std::vector<std::string> extra_names;
  std::optional<TempFile> temp;
  std::unique_ptr<OIIO::Filesystem::IOVecOutput> memory;
  std::unique_ptr<OIIO::ImageOutput> out;
  int rows = 0;
  PreparedImage band;  ///< the band's converted pixels, its buffers kept from band to band
};

/// Opens `state`'s writer on its target (its temporary file, or memory): the spec of a
/// `width` x `height` image in `format`.
void open_stream(OiioStream& state, FileFormat format, int width, int height,
                 const ImageWriteOptions& options) {
  if (width <= 0 || height <= 0) {
    throw std::runtime_error(state.what + ": image has no pixels (" + std::to_string(width) + "x" +
                             std::to_string(height) + ")");
  }
  state.format = format;
  state.width = width;
  state.height = height;
  state.half = options.half;
  for (const ExtraChannel& extra : options.extra_channels) state.extra_names.push_back(extra.name);
  state.out = create_output(format, state.what, state.memory.get());
  const std::string name = state.temp ? state.temp->path().string()
                           : format == FileFormat::kExr ? "memory.exr"
                                                        : "memory.png";
  if (!state.out->open(name, file_spec(width, height, format, options))) {
    throw std::runtime_error(state.what + ": " + state.out->geterror());
  }
}

/// A stream on a file (ImageFileStream's constructor).
std::unique_ptr<OiioStream> open_file_stream(const std::filesystem::path& path, int width, int height,
                                             const ImageWriteOptions& options) {
  const std::string what = "cannot write image '" + path.string() + "'";
  const std::optional<FileFormat> format = format_from_extension(path.extension().string());
  if (!format) {
    throw std::runtime_error(what + ": unsupported extension '" + path.extension().string() +
                             "' (supported: " + kSupportedExtensions + ")");
  }
  auto state = std::make_unique<OiioStream>();
  state->path = path;
  state->what = what;
  if (width > 0 && height > 0) {
    // Written beside the destination and renamed over it by finish(): readers see the old file
    // or the whole new one, never a partial image, even if this process dies midway.
    state->temp.emplace(path);
  }
  open_stream(*state, *format, width, height, options);
  return state;
}

/// A stream into memory (ImageFileStream::in_memory).
std::unique_ptr<OiioStream> open_memory_stream(const std::string& format, int width, int height,
                                               const ImageWriteOptions& options) {
  const std::string what = "cannot encode image as '" + format + "'";
  const std::optional<FileFormat> file_format = format_from_extension(format);
  if (!file_format) throw std::runtime_error(what + ": unsupported format (supported: exr, png)");
  auto state = std::make_unique<OiioStream>();
  state->what = what;
  state->memory = std::make_unique<OIIO::Filesystem::IOVecOutput>();
  open_stream(*state, *file_format, width, height, options);
  return state;
}

void write_rows(OiioStream& s, const RgbImage& band, const std::vector<ExtraChannel>& extra) {
  if (band.width != s.width || band.height <= 0 || band.height > s.height - s.rows ||
      band.rgb.size() != size_t(band.width) * size_t(band.height) * 3) {
    throw std::runtime_error(s.what + ": a band of " + std::to_string(band.width) + "x" + std::to_string(band.height) +
                             " (" + std::to_string(band.rgb.size()) + " floats) at row " + std::to_string(s.rows) +
                             " does not fit a " + std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
  }
  if (s.format == FileFormat::kExr) {
    if (extra.size() != s.extra_names.size()) {
      throw std::runtime_error(s.what + ": " + std::to_string(extra.size()) + " extra channels for " +
                               std::to_string(s.extra_names.size()));
    }
    convert_pixels(band, s.format, s.half, extra, &s.band);
  } else {
    convert_pixels(band, s.format, s.half, {}, &s.band);  // PNG has no room for extra channels
  }
  if (!s.out->write_scanlines(s.rows, s.rows + band.height, 0, s.band.data_type(), s.band.data())) {
    throw std::runtime_error(s.what + ": " + s.out->geterror());
  }
  s.rows += band.height;
}

/// Closes the stream: its file goes into place; returns an in-memory stream's bytes ("" for a
/// file).
std::string finish(OiioStream& s) {
  if (s.rows != s.height) {
    throw std::runtime_error(s.what + ": " + std::to_string(s.rows) + " of " + std::to_string(s.height) +
                             " rows written");
  }
  if (!s.out->close()) throw std::runtime_error(s.what + ": " + s.out->geterror());
  s.out.reset();
  if (s.memory) {
    const std::vector<unsigned char>& bytes = s.memory->buffer();
    return std::string(bytes.begin(), bytes.end());
  }
  fsync_path(s.temp->path(), true, s.what);
  std::error_code error;
  std::filesystem::rename(s.temp->path(), s.path, error);
  if (error) throw std::runtime_error(s.what + ": cannot rename the temporary file: " + error.message());
  s.temp->release();
  const std::filesystem::path folder = s.path.parent_path().empty() ? "." : s.path.parent_path();
  fsync_path(folder, false, s.what);  // best effort: some file systems refuse to sync a folder
  return {};
}

void oiio_write_image(const RgbImage& image, const std::filesystem::path& path,
                      const ImageWriteOptions& options) {
  // The stream checks the extension; the image's size is checked first, so that a mismatch
  // is named as such and no temporary file is made.
  check_dimensions(image, "cannot write image '" + path.string() + "'");
  // One band: the whole image.
  const std::unique_ptr<OiioStream> stream = open_file_stream(path, image.width, image.height, options);
  write_rows(*stream, image, options.extra_channels);
  finish(*stream);
}

std::string oiio_encode_image(const RgbImage& image, const std::string& format,
                              const ImageWriteOptions& options) {
  check_dimensions(image, "cannot encode image as '" + format + "'");  // the stream checks the format
  const std::unique_ptr<OiioStream> stream = open_memory_stream(format, image.width, image.height, options);
  write_rows(*stream, image, options.extra_channels);
  return finish(*stream);
}

RgbImage oiio_read_image(const std::filesystem::path& path) {
  const std::string what = "cannot read image '" + path.string() + "'";
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error(what + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    throw std::runtime_error(what + ": it has no pixels");
  }
  const int channels = std::min(spec.nchannels, 3);
  const size_t pixels = size_t(spec.width) * size_t(spec.height);
  std::vector<float> read(pixels * size_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, read.data())) {
    throw std::runtime_error(what + ": " + in->geterror());
  }
  const bool srgb = is_srgb_encoded(spec);
  in->close();

  RgbImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgb.resize(pixels * 3);
  for (size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c) {
      // One or two channels (grey, grey + alpha): the first is replicated.
      const float v = read[p * channels + (channels == 3 ? c : 0)];
      image.rgb[p * 3 + c] = srgb ? srgb_to_linear(v) : v;
    }
  }
  return image;
}

// The stream through an opaque handle, as the table hands it out. Deleting an unfinished
// stream (an exception on the way) closes OIIO's writer first, then removes the temporary file.
void* stream_open(const std::filesystem::path& path, int width, int height, const ImageWriteOptions& options) {
  return open_file_stream(path, width, height, options).release();
}
void* stream_open_in_memory(const std::string& format, int width, int height, const ImageWriteOptions& options) {
  return open_memory_stream(format, width, height, options).release();
}
void stream_write_rows(void* stream, const RgbImage& band, const std::vector<ExtraChannel>& extra) {
  write_rows(*static_cast<OiioStream*>(stream), band, extra);
}
std::string stream_finish(void* stream) { return finish(*static_cast<OiioStream*>(stream)); }
void stream_delete(void* stream) { delete static_cast<OiioStream*>(stream); }

}  // namespace

const ImageIo& oiio_image_io() {
  static const ImageIo table{&oiio_write_image,       &oiio_encode_image, &oiio_read_image,
                             &stream_open,            &stream_open_in_memory,
                             &stream_write_rows,      &stream_finish,    &stream_delete,
                             &oiio_check_image_bytes, &oiio_probe_image_bytes};
  return table;
}

}  // namespace tessera
