// Output paths given on a command line (`-o`), checked before any work starts: a render or a job
// that cannot write its result is refused up front, not after it has run.
#pragma once

#include <string>
#include <vector>

namespace tessera::cli {

/// Checks that `path` ends in one of `extensions` (lower case, with the dot, compared without
/// case), that its folder exists and is writable and that `path` is not a folder. Throws
/// std::runtime_error naming the path and what is wrong, e.g.
/// "-o /nonexistent/dir/x.png: folder /nonexistent/dir does not exist". Whether the folder takes
/// a new file is tried (a file created and removed at once); nothing else is written.
void check_output_path(const std::string& path, const std::vector<std::string>& extensions);

}  // namespace tessera::cli
