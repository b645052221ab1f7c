#include "build_info.h"

#include "tessera_commit.h"  // generated at build time (cmake/write_commit_header.cmake)

namespace tessera {

const char* build_commit() { return TESSERA_COMMIT; }

const char* build_compiler() { return TESSERA_COMPILER; }

std::string build_version(const std::string& more) {
  return std::string(TESSERA_VERSION " (commit ") + build_commit() + ", " + build_compiler() +
         (more.empty() ? "" : ", " + more) + ")";
}

}  // namespace tessera
