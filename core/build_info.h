// Which build a Tessera program is: its version, the commit it was built from, its compiler.
#pragma once

#include <string>

namespace tessera {

/// The commit the program was built from: git's 12-digit short hash, with "-dirty" when built
/// with uncommitted changes to tracked files; what the build was given as TESSERA_COMMIT where
/// the source is no git checkout (deploy/Dockerfile); else "unknown". Written at every build
/// (cmake/write_commit_header.cmake).
const char* build_commit();
/// The compiler, as CMake names it: "GNU 12.2.0", "Clang 14.0.6".
const char* build_compiler();
/// "0.1.0 (commit 4658ccee21cf, GNU 12.2.0)": what `--version` prints after the program's name.
/// `more`, when given, is named after the compiler inside the parentheses: the renderer's build
/// adds Embree and the C library that way (worker/render/renderer_build.h).
std::string build_version(const std::string& more = std::string());

}  // namespace tessera
