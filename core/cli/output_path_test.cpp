#include "cli/output_path.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <stdexcept>

namespace tessera::cli {
namespace {

std::string output_path_error(const std::string& path) {
  try {
    check_output_path(path, {".exr", ".png"});
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(OutputPath, AcceptsAWritableFolderAndRefusesTheRestBeforeAnyWork) {
  const auto dir = std::filesystem::temp_directory_path() / "tessera_output_path_test";
  std::filesystem::create_directories(dir / "x.png");
  EXPECT_EQ(output_path_error((dir / "a.exr").string()), "(accepted)");
  EXPECT_EQ(output_path_error((dir / "A.PNG").string()), "(accepted)");
  EXPECT_EQ(output_path_error("relative.png"), "(accepted)");
  EXPECT_EQ(output_path_error("/nonexistent/dir/x.png"),
            "-o /nonexistent/dir/x.png: folder /nonexistent/dir does not exist");
  EXPECT_EQ(output_path_error((dir / "x.png").string()), "-o " + (dir / "x.png").string() + ": is a folder");
  EXPECT_EQ(output_path_error((dir / "x.png" / "y.tiff").string()),
            "-o " + (dir / "x.png" / "y.tiff").string() + ": the output must end in .exr or .png");
  EXPECT_EQ(output_path_error("/etc/passwd/x.png"), "-o /etc/passwd/x.png: /etc/passwd is not a folder");
  // Nothing is left behind by the check.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
  std::filesystem::remove_all(dir);
}

TEST(OutputPath, AFolderThatTakesNoNewFileIsRefusedEvenForRoot) {
  // /proc refuses a new file to every user, root included, for whom access(W_OK) says yes.
  if (!std::filesystem::is_directory("/proc/self")) GTEST_SKIP() << "no /proc here";
  const std::string error = output_path_error("/proc/version.png");
  EXPECT_EQ(error.rfind("-o /proc/version.png: cannot write in folder /proc: ", 0), 0u) << error;
}

}  // namespace
}  // namespace tessera::cli
