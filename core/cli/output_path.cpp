#include "cli/output_path.h"

#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace tessera::cli {

void check_output_path(const std::string& path, const std::vector<std::string>& extensions) {
  namespace fs = std::filesystem;
  const std::string where = "-o " + path + ": ";
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  bool known = false;
  std::string list;
  for (const std::string& e : extensions) {
    known = known || e == ext;
    list += (list.empty() ? "" : " or ") + e;
  }
  if (!known) throw std::runtime_error(where + "the output must end in " + list);

  std::error_code ec;
  if (fs::is_directory(fs::status(path, ec))) throw std::runtime_error(where + "is a folder");
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  const fs::file_status status = fs::status(folder, ec);
  if (!fs::exists(status)) {
    throw std::runtime_error(where + "folder " + folder.string() + " does not exist");
  }
  if (!fs::is_directory(status)) {
    throw std::runtime_error(where + folder.string() + " is not a folder");
  }
  // The image is written through a temporary file beside it and renamed: the folder must be
  // writable, and an existing file is replaced.
  // access() answers yes for root whatever the folder (/proc, a read-only mount): try what the
  // write will do, a new file in the folder, and remove it at once.
  std::string probe = (folder / ".tessera-write-check-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) {
    throw std::runtime_error(where + "cannot write in folder " + folder.string() + ": " +
                             std::strerror(errno));
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace tessera::cli
