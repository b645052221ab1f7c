// The `tessera-worker converge` subcommand (docs/accuracy.md): its options and what it runs.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "job/job_options.h"

namespace tessera {

struct ConvergeCommand {
  std::string scene;
  std::string reference;
  std::string csv, markdown, plot;
  std::string images;        ///< --images DIR: each level's raw (and denoised) image as EXR
  bool denoise = false;      ///< --denoise: each level denoised and measured as well
  std::string oidn_library;  ///< --oidn-library
  JobOverrides overrides;
  uint32_t fit_from = 4;
  int threads = 0;
  bool quiet = false;
  CLI::App* app = nullptr;

  /// Registers the subcommand and its options on `parent`.
  void add_to(CLI::App& parent);
  /// Runs it: renders, prints the Markdown table to stdout and writes the files asked for.
  /// Throws with a one-line message on bad input.
  int run() const;
};

}  // namespace tessera
