#include "renderer_build.h"

#include <embree3/rtcore.h>
#include <gnu/libc-version.h>

#include "build_info.h"

namespace tessera {

std::string renderer_build() {
  return std::string(TESSERA_VERSION " (commit ") + build_commit() + ", " + build_compiler() +
         ", Embree " RTC_VERSION_STRING ", glibc " + gnu_get_libc_version() + ")";
}

}  // namespace tessera
