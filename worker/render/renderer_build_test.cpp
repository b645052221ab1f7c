#include "renderer_build.h"

#include <embree3/rtcore.h>
#include <gnu/libc-version.h>
#include <gtest/gtest.h>

#include <string>

#include "build_info.h"

namespace tessera {
namespace {

TEST(RendererBuild, NamesTheProgramsBuildThenEmbreeAndTheCLibrary) {
  // The program's build (core/build_info.h, tested there), then what the renderer runs with.
  EXPECT_EQ(renderer_build(), std::string(TESSERA_VERSION) + " (commit " + build_commit() + ", " +
                                  build_compiler() + ", Embree " RTC_VERSION_STRING ", glibc " +
                                  gnu_get_libc_version() + ")");
}

}  // namespace
}  // namespace tessera
