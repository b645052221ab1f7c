// The image functions and ImageFileStream's members: each calls the one implementation through
// image_io() (image_io.h), which is OpenImageIO linked in or the image module.
#include "image/image_output.h"

#include <stdexcept>
#include <utility>

#include "image/image_io.h"

namespace tessera {

void write_image(const RgbImage& image, const std::filesystem::path& path,
                 const ImageWriteOptions& options) {
  image_io().write_image(image, path, options);
}

std::string encode_image(const RgbImage& image, const std::string& format,
                         const ImageWriteOptions& options) {
  return image_io().encode_image(image, format, options);
}

RgbImage read_image(const std::filesystem::path& path) { return image_io().read_image(path); }

// state_ holds the implementation's own stream (an opaque handle here, never dereferenced).
ImageFileStream::ImageFileStream(const std::filesystem::path& path, int width, int height,
                                 const ImageWriteOptions& options)
    : state_(static_cast<State*>(image_io().stream_open(path, width, height, options))) {}

ImageFileStream ImageFileStream::in_memory(const std::string& format, int width, int height,
                                           const ImageWriteOptions& options) {
  ImageFileStream stream;
  stream.state_ =
      static_cast<State*>(image_io().stream_open_in_memory(format, width, height, options));
  return stream;
}

ImageFileStream::ImageFileStream(ImageFileStream&& other) noexcept
    : state_(std::exchange(other.state_, nullptr)), bytes_(std::move(other.bytes_)) {}

ImageFileStream& ImageFileStream::operator=(ImageFileStream&& other) noexcept {
  if (this != &other) {
    if (state_) image_io().stream_delete(state_);
    state_ = std::exchange(other.state_, nullptr);
    bytes_ = std::move(other.bytes_);
  }
  return *this;
}

ImageFileStream::~ImageFileStream() {
  // Unfinished (an exception on the way): the temporary file goes with it.
  if (state_) image_io().stream_delete(state_);
}

void ImageFileStream::write_rows(const RgbImage& band, const std::vector<ExtraChannel>& extra) {
  if (!state_) throw std::logic_error("ImageFileStream::write_rows after finish");
  image_io().stream_write_rows(state_, band, extra);
}

void ImageFileStream::finish() {
  if (!state_) throw std::logic_error("ImageFileStream::finish called twice");
  bytes_ = image_io().stream_finish(state_);
  image_io().stream_delete(std::exchange(state_, nullptr));
}

std::string ImageFileStream::take_bytes() { return std::exchange(bytes_, std::string()); }

}  // namespace tessera
