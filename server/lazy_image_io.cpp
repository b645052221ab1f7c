// The image functions (image/image_output.h, scene/image_check.h) of tessera-server and of the
// tessera client: each forwards to the image module (server/image_io_table.h), loaded by the
// first call (or load_image_module, which the server's main calls on a thread once it listens),
// so that the server maps OpenImageIO's ~250 libraries after it listens, not before, and a
// client command maps them only when it checks a scene's images. The module is embedded in the
// executable (a container copies one file) and loaded from an anonymous memory file
// (memfd_create).
//
// Linked into each executable before tessera_core, these definitions keep the linker from taking
// core's image_output.o and image_check.o out of the archive, so the executable does not need
// OpenImageIO (tests/dashboard/start_libraries.sh: server_start_libraries,
// client_start_libraries).
#include <dlfcn.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "image_io_table.h"
#include "lazy_image_io.h"

// The module's bytes (TESSERA_IMAGE_MODULE: its path at build time). ccache does not cache a
// file with .incbin, so a changed module is always embedded again.
__asm__(
    ".pushsection .rodata\n"
    ".balign 64\n"
    "tessera_image_module_begin:\n"
    ".incbin \"" TESSERA_IMAGE_MODULE "\"\n"
    "tessera_image_module_end:\n"
    ".popsection\n");
extern "C" const char tessera_image_module_begin[];
extern "C" const char tessera_image_module_end[];

namespace tessera {
namespace {

std::runtime_error load_error(const std::string& what) {
  return std::runtime_error("cannot load the image module (OpenImageIO): " + what);
}

const server::ImageIoTable* load_image_module() {
  const int fd = memfd_create("tessera-image-module.so", MFD_CLOEXEC);
  if (fd < 0) throw load_error(std::string("memfd_create: ") + std::strerror(errno));
  const char* p = tessera_image_module_begin;
  while (p < tessera_image_module_end) {
    const ssize_t n = ::write(fd, p, size_t(tessera_image_module_end - p));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = errno;
      ::close(fd);
      throw load_error(std::string("writing it: ") + std::strerror(error));
    }
    p += n;
  }
  // Never unloaded: the table's functions stay valid for the process's life.
  void* module = dlopen(("/proc/self/fd/" + std::to_string(fd)).c_str(), RTLD_NOW | RTLD_LOCAL);
  ::close(fd);  // the mapping keeps the file
  if (!module) throw load_error(dlerror());
  using Getter = const server::ImageIoTable* (*)();
  const auto getter = reinterpret_cast<Getter>(dlsym(module, "tessera_image_io_table"));
  if (!getter) throw load_error(dlerror());
  const server::ImageIoTable* table = getter();
  if (table->version != server::kImageIoTableVersion) {
    throw load_error("table version " + std::to_string(table->version) + ", expected " +
                     std::to_string(server::kImageIoTableVersion));
  }
  return table;
}

/// The module's table, loaded by the first caller (thread-safe; a failed load is tried again by
/// the next call).
const server::ImageIoTable& image_io() {
  static const server::ImageIoTable* const table = load_image_module();
  return *table;
}

}  // namespace

void server::load_image_module() { image_io(); }

void write_image(const RgbImage& image, const std::filesystem::path& path,
                 const ImageWriteOptions& options) {
  image_io().write_image(image, path, options);
}

std::string encode_image(const RgbImage& image, const std::string& format,
                         const ImageWriteOptions& options) {
  return image_io().encode_image(image, format, options);
}

// ImageFileStream: state_ holds the module's own ImageFileStream (an opaque handle here, never
// dereferenced as a State).
ImageFileStream::ImageFileStream(const std::filesystem::path& path, int width, int height,
                                 const ImageWriteOptions& options)
    : state_(static_cast<State*>(image_io().stream_open(path, width, height, options))) {}

ImageFileStream ImageFileStream::in_memory(const std::string& format, int width, int height,
                                           const ImageWriteOptions& options) {
  ImageFileStream stream;
  stream.state_ = static_cast<State*>(image_io().stream_open_in_memory(format, width, height, options));
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

RgbImage read_image(const std::filesystem::path& path) { return image_io().read_image(path); }

float linear_to_srgb(float linear) { return image_io().linear_to_srgb(linear); }

ImageCheck check_image_bytes(const std::string& path, std::string_view bytes) {
  return image_io().check_image_bytes(path, bytes);
}

std::vector<std::string> scene_image_files(const Scene& scene) {
  return image_io().scene_image_files(scene);
}

}  // namespace tessera
