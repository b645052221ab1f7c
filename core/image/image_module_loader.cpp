// Where the image module is loaded (tessera-server, the tessera client; image_module.h):
// image_io() is the module's table, loaded by the first call, or by load_image_module. The
// module is embedded in the executable (a container copies one file) and loaded from an
// anonymous memory file (memfd_create). Never unloaded: its functions stay valid for the
// process's life.
#include <dlfcn.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

#include "image/image_module.h"

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

/// The embedded module in an anonymous memory file; returns its descriptor.
int module_file() {
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
  return fd;
}

const ImageModule* load_module() {
  const int fd = module_file();
  void* module = dlopen(("/proc/self/fd/" + std::to_string(fd)).c_str(), RTLD_NOW | RTLD_LOCAL);
  ::close(fd);  // the mapping keeps the file
  if (!module) throw load_error(dlerror());
  using Getter = const ImageModule* (*)();
  const auto getter = reinterpret_cast<Getter>(dlsym(module, "tessera_image_module"));
  if (!getter) throw load_error(dlerror());
  const ImageModule* loaded = getter();
  if (loaded->version != kImageModuleVersion) {
    throw load_error("version " + std::to_string(loaded->version) + ", expected " +
                     std::to_string(kImageModuleVersion));
  }
  return loaded;
}

/// The module, loaded by the first caller (thread-safe; a failed load is tried again by the
/// next call).
const ImageModule& image_module() {
  static const ImageModule* const module = load_module();
  return *module;
}

}  // namespace

void load_image_module() { image_module(); }

const ImageIo& image_io() { return *image_module().io; }

}  // namespace tessera
