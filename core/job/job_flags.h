// The job options a user may override, as command-line flags: one definition, so that
// `tessera submit` and `tessera-worker render` take the same names with the same meanings (the
// same command line means the same job, and the same bits: job_options.h).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "job/job_options.h"

namespace tessera {

/// Adds a flag that sets `target` only when given (an unset optional keeps the scene's value).
template <typename T>
CLI::Option* add_optional_flag(CLI::App* command, const std::string& name,
                               std::optional<T>& target, const std::string& help) {
  return command->add_option_function<T>(name, [&target](const T& v) { target = v; }, help);
}

/// The check of --seed: a decimal integer in [0, 2^64-1], read without wrapping (CLI11 alone
/// would turn 2^64 into 2^63-1 and -1 into a huge number).
inline CLI::Validator seed_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        static const std::string kMax = "18446744073709551615";
        const size_t first = text.find_first_not_of('0');
        const std::string digits = first == std::string::npos ? "0" : text.substr(first);
        const bool in_range =
            !text.empty() && text.find_first_not_of("0123456789") == std::string::npos &&
            (digits.size() < kMax.size() || (digits.size() == kMax.size() && digits <= kMax));
        if (in_range) return {};
        return "must be in [0, 2^64-1] (got " + text + ")";
      },
      "UINT64");
}

/// The overrides alone, checked with the same function that resolves a job
/// (resolve_job_options) against a scene whose own values are all valid: whatever it refuses is
/// the flags' fault, a usage error (CLI::ValidationError, exit status 2), reported before any
/// scene is read. What depends on the scene or the server's limits is checked later.
inline void check_job_override_flags(const JobOverrides& overrides) {
  try {
    resolve_job_options(Scene{}, overrides);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(e.what());
  }
}

/// --spp/--time/--noise/--max-spp/--preset (the stopping rule, docs/accuracy.md), --width,
/// --height, --tile, --batch, --seed, --max-depth and --isa, each filling `overrides`.
/// The flags are checked when `command` is parsed (check_job_override_flags): a bad value is a
/// parse error naming the flag.
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
  add_optional_flag(command, "--seed", overrides.seed,
                    "Random seed in [0, 2^64-1] (default: the scene's)")
      ->check(seed_check());
  add_optional_flag(command, "--max-depth", overrides.max_depth,
                    "Path segments including the camera ray, -1 = unbounded (Mitsuba's convention)");
  add_optional_flag(command, "--isa", overrides.isa,
                    "Pin Embree's instruction set on every worker (sse2, sse4.2, avx, avx2, avx512)");
  command->final_callback([&overrides] { check_job_override_flags(overrides); });
}

}  // namespace tessera
