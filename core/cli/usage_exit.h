// The exit statuses every Tessera binary (tessera-server, tessera-worker, tessera) uses, and how a
// command-line parse error becomes one (docs/design.md, "Exit statuses").
#pragma once

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

namespace tessera::cli {

inline constexpr int kExitSuccess = 0;
/// Everything that is not a usage error: a bad scene, a refused or failed job, I/O.
inline constexpr int kExitFailure = 1;
/// The command line itself is wrong: an unknown flag, a value that does not parse or is out of
/// range, a missing argument.
inline constexpr int kExitUsage = 2;

/// What `main` returns after `app.parse` threw `error`: --help and --version print to stdout and
/// give 0; every other parse error is written as one line "PROGRAM: MESSAGE (see --help)" on
/// stderr and gives kExitUsage (CLI11's own codes, 100 and up, are never returned).
inline int exit_for_parse_error(const CLI::App& app, const CLI::ParseError& error,
                                const char* program) {
  if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
    return app.exit(error);  // --help, --help-all, --version: printed on stdout
  }
  std::fprintf(stderr, "%s: %s (see --help)\n", program, error.what());
  return kExitUsage;
}

}  // namespace tessera::cli
