#include "build_info.h"

#include <gtest/gtest.h>

#include <regex>
#include <string>

namespace tessera {
namespace {

TEST(BuildInfo, VersionNamesTheCommitAndTheCompiler) {
  // git's 12 hex digits, maybe "-dirty"; "unknown" outside a git checkout; or what the build
  // was given as TESSERA_COMMIT (cmake/write_commit_header.cmake).
  const std::string commit = build_commit();
  EXPECT_TRUE(std::regex_match(commit, std::regex("[0-9A-Za-z._-]+"))) << commit;
  const std::string compiler = build_compiler();
#if defined(__clang__)
  EXPECT_EQ(compiler.rfind("Clang " + std::to_string(__clang_major__) + ".", 0), 0u) << compiler;
#elif defined(__GNUC__)
  EXPECT_EQ(compiler.rfind("GNU " + std::to_string(__GNUC__) + ".", 0), 0u) << compiler;
#endif
  EXPECT_EQ(build_version(), std::string(TESSERA_VERSION) + " (commit " + commit + ", " + compiler + ")");
}

}  // namespace
}  // namespace tessera
