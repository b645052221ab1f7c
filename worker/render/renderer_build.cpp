#include "renderer_build.h"

#include <embree3/rtcore.h>
#include <gnu/libc-version.h>

#include "build_info.h"

namespace tessera {

std::string renderer_build() {
  return build_version("Embree " RTC_VERSION_STRING ", glibc " + std::string(gnu_get_libc_version()));
}

}  // namespace tessera
