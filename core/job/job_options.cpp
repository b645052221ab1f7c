#include "job/job_options.h"

#include <array>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

[[noreturn]] void bad(const std::string& option, const std::string& rule, int64_t got) {
  throw std::invalid_argument(option + ": " + rule + " (got " + std::to_string(got) + ")");
}

int64_t in_range(const char* option, int64_t value, int64_t lo, int64_t hi) {
  if (value < lo || value > hi) {
    bad(option, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", value);
  }
  return value;
}

}  // namespace

JobPlan JobOptions::plan() const {
  return make_job_plan(width, height, tile_size, spp, batch_spp);
}

JobOptions resolve_job_options(const Scene& scene, const JobOverrides& o, const JobLimits& limits) {
  JobOptions job;
  job.width = int(in_range("--width", o.width.value_or(scene.film.width), 1, limits.max_dimension));
  job.height =
      int(in_range("--height", o.height.value_or(scene.film.height), 1, limits.max_dimension));
  job.spp = uint32_t(in_range("--spp", o.spp.value_or(scene.render.spp), 1, limits.max_spp));
  const int depth = o.max_depth.value_or(scene.render.max_depth);
  if (depth != -1 && depth < 1) bad("--max-depth", "must be -1 (unbounded) or >= 1", depth);
  job.max_depth = depth;
  const int64_t seed = o.seed.has_value() ? *o.seed : int64_t(scene.render.seed);
  if (seed < 0) bad("--seed", "must be >= 0", seed);
  job.seed = uint64_t(seed);
  job.tile_size = int(in_range("--tile", o.tile_size.value_or(64), 1, limits.max_tile));
  const int64_t batch = o.batch_spp.value_or(0);
  if (o.batch_spp.has_value()) in_range("--batch", batch, 1, limits.max_spp);
  job.batch_spp = make_job_plan(job.width, job.height, job.tile_size, job.spp, uint32_t(batch))
                      .batch_spp;
  if (o.isa.has_value()) {
    static constexpr std::array<const char*, 5> kIsas = {"sse2", "sse4.2", "avx", "avx2",
                                                         "avx512"};
    bool known = false;
    for (const char* isa : kIsas) known = known || *o.isa == isa;
    if (!known) {
      throw std::invalid_argument("--isa: unknown instruction set \"" + *o.isa +
                                  "\" (use sse2, sse4.2, avx, avx2 or avx512)");
    }
    job.isa = *o.isa;
  }
  return job;
}

}  // namespace tessera
