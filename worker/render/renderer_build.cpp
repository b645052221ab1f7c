#include "renderer_build.h"

#include <embree3/rtcore.h>
#include <gnu/libc-version.h>

#include "tessera_commit.h"  // generated at build time (cmake/write_commit_header.cmake)

namespace tessera {

std::string renderer_build() {
  return std::string(TESSERA_VERSION " (commit " TESSERA_COMMIT ", " TESSERA_COMPILER ", Embree " RTC_VERSION_STRING
                     ", glibc ") +
         gnu_get_libc_version() + ")";
}

}  // namespace tessera
