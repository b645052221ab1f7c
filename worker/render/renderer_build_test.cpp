#include "renderer_build.h"

#include <embree3/rtcore.h>
#include <gnu/libc-version.h>
#include <gtest/gtest.h>

#include <regex>

namespace tessera {
namespace {

TEST(RendererBuild, NamesTheVersionCommitCompilerEmbreeAndCLibrary) {
  const std::string build = renderer_build();
  EXPECT_EQ(build.rfind(TESSERA_VERSION " (commit ", 0), 0u) << build;
  // git's 12 hex digits, maybe "-dirty"; "unknown" outside a git checkout; or what the build
  // was given as TESSERA_COMMIT (cmake/write_commit_header.cmake).
  EXPECT_TRUE(std::regex_search(build, std::regex(R"(\(commit [0-9A-Za-z._-]+, )"))) << build;
#if defined(__clang__)
  EXPECT_NE(build.find(", Clang " + std::to_string(__clang_major__) + "."), std::string::npos) << build;
#elif defined(__GNUC__)
  EXPECT_NE(build.find(", GNU " + std::to_string(__GNUC__) + "."), std::string::npos) << build;
#endif
  EXPECT_NE(build.find(", Embree " RTC_VERSION_STRING ", "), std::string::npos) << build;
  EXPECT_NE(build.find(std::string(", glibc ") + gnu_get_libc_version() + ")"), std::string::npos) << build;
}

}  // namespace
}  // namespace tessera
