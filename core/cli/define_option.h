// The -D name=value option of `tessera submit`, `tessera-worker render` and `convert`: Mitsuba
// parameters (docs/mitsuba.md), checked while the command line is parsed, so that a malformed or
// repeated -D is a usage error (exit 2, docs/design.md "Exit statuses") found before any file
// is read.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_parameters.h"
#include "scene/scene_error.h"

namespace tessera::cli {

inline constexpr const char* kDefineHelp =
    "name=value: the Mitsuba scene's parameter $name, overriding its <default> (repeatable)";

/// Adds -D to `command`, storing each value in `defines`. Once the command line is parsed, each
/// value must parse as parse_mitsuba_define() says, and no name may be given twice: otherwise
/// parsing throws CLI::ValidationError with parse_mitsuba_defines()'s message ("-D x: ...").
inline CLI::Option* add_define_option(CLI::App* command, std::vector<std::string>& defines) {
  command->parse_complete_callback([&defines] {
    try {
      parse_mitsuba_defines(defines);
    } catch (const SceneError& e) {
      throw CLI::ValidationError(e.what());
    }
  });
  // One value per -D: "-D a=1 scene.xml" must leave scene.xml to the positional argument.
  return command->add_option("-D", defines, kDefineHelp)->allow_extra_args(false);
}

}  // namespace tessera::cli
