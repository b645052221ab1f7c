// The job options a user may override, as command-line flags: one definition, so that
// `tessera submit` and `tessera-worker render` take the same names with the same meanings (the
// same command line means the same job, and the same bits: job_options.h).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "job/job_options.h"

namespace tessera {

/// Adds a flag that sets `target` only when given (an unset optional keeps the scene's value).
template <typename T>
void add_optional_flag(CLI::App* command, const std::string& name, std::optional<T>& target,
                       const std::string& help) {
  command->add_option_function<T>(name, [&target](const T& v) { target = v; }, help);
}

/// --spp/--time/--noise/--max-spp/--preset (the stopping rule, docs/accuracy.md), --width,
/// --height, --tile, --batch, --seed, --max-depth and --isa, each filling `overrides`.
/// resolve_job_options checks the values and names the flag of a bad one.
inline void add_job_override_flags(CLI::App* command, JobOverrides& overrides) {
  add_optional_flag(command, "--spp", overrides.spp,
                    "Stopping rule: exactly N samples per pixel (default: the scene's)");
  add_optional_flag(command, "--time", overrides.time_s,
                    "Stopping rule: start no batch after this many seconds; keep what is merged");
  add_optional_flag(command, "--noise", overrides.noise,
                    "Stopping rule: sample each tile until its estimated relative error is at "
                    "most E");
  add_optional_flag(command, "--max-spp", overrides.max_spp,
                    "Cap of a --noise or --time job in samples per pixel (default 4096)");
  add_optional_flag(command, "--preset", overrides.preset,
                    "Quality preset: draft, preview, final, reference (docs/accuracy.md)");
  add_optional_flag(command, "--width", overrides.width, "Image width in pixels");
  add_optional_flag(command, "--height", overrides.height, "Image height in pixels");
  add_optional_flag(command, "--tile", overrides.tile_size, "Tile size in pixels (default 64)");
  add_optional_flag(command, "--batch", overrides.batch_spp,
                    "Samples per pixel in one work unit (default: derived from the job)");
  add_optional_flag(command, "--seed", overrides.seed, "Random seed (default: the scene's)");
  add_optional_flag(command, "--max-depth", overrides.max_depth,
                    "Path segments including the camera ray, -1 = unbounded (Mitsuba's convention)");
  add_optional_flag(command, "--isa", overrides.isa,
                    "Pin Embree's instruction set on every worker (sse2, sse4.2, avx, avx2, avx512)");
}

}  // namespace tessera
