#include "job/job_options.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

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

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

double positive(const char* option, double value, double hi) {
  if (!std::isfinite(value) || value <= 0) {
    throw std::invalid_argument(std::string(option) + ": must be > 0 (got " + number(value) + ")");
  }
  if (value > hi) {
    throw std::invalid_argument(std::string(option) + ": must be at most " + number(hi) +
                                " (got " + number(value) + ")");
  }
  return value;
}

/// The rule the overrides (or the scene's render.spp) ask for, with its values, before the plan.
struct ResolvedRule {
  StopRule rule = StopRule::spp;
  int64_t spp = 0;  ///< spp rule: N; others: the cap
  double time_s = 0, noise = 0;
};

ResolvedRule resolve_rule(const Scene& scene, const JobOverrides& o, const JobLimits& limits) {
  std::vector<std::string> given;
  if (o.spp) given.push_back("--spp");
  if (o.time_s) given.push_back("--time");
  if (o.noise) given.push_back("--noise");
  if (o.preset) given.push_back("--preset");
  if (given.size() > 1) {
    throw std::invalid_argument(given[0] + " and " + given[1] +
                                " are mutually exclusive: give one stopping rule");
  }
  ResolvedRule r;
  std::optional<double> noise = o.noise;
  std::optional<int64_t> cap = o.max_spp;
  if (o.preset) {
    const std::optional<QualityPreset> p = find_preset(*o.preset);
    if (!p) {
      std::string names;
      for (const QualityPreset& q : quality_presets()) {
        names += (names.empty() ? "" : ", ") + std::string(q.name);
      }
      throw std::invalid_argument("--preset: unknown preset \"" + *o.preset + "\" (use " + names +
                                  ")");
    }
    if (p->rule == StopRule::spp) {
      if (o.max_spp) {
        throw std::invalid_argument("--max-spp: only with --noise, --time or a noise preset (" +
                                    std::string(p->name) + " is " + std::to_string(p->spp) +
                                    " spp)");
      }
      r.spp = p->spp;
      return r;
    }
    noise = p->noise;
    if (!cap) cap = p->max_spp;
  }
  if (!noise && !o.time_s) {
    if (o.max_spp) throw std::invalid_argument("--max-spp: only with --noise, --time or a noise preset");
    // A value from the scene is named as the scene's, so that the user looks in the file.
    r.spp = in_range(o.spp ? "--spp" : "the scene's spp (render.spp; --spp overrides it)",
                     o.spp.value_or(scene.render.spp), 1, limits.max_spp);
    return r;
  }
  r.spp = in_range("--max-spp", cap.value_or(kDefaultMaxSpp), 1, limits.max_spp);
  if (noise) {
    r.rule = StopRule::noise;
    r.noise = positive("--noise", *noise, 1e6);
  } else {
    r.rule = StopRule::time;
    r.time_s = positive("--time", *o.time_s, 30.0 * 86400.0);
  }
  return r;
}

}  // namespace

JobPlan JobOptions::plan() const {
  return make_job_plan(width, height, tile_size, spp, batch_spp, batch_kind);
}

JobOptions resolve_job_options(const Scene& scene, const JobOverrides& o, const JobLimits& limits) {
  JobOptions job;
  // A value from the scene is named as the scene's, so that the user looks in the file.
  job.width = int(in_range(o.width ? "--width" : "the scene's width (film.width; --width overrides it)",
                           o.width.value_or(scene.film.width), 1, limits.max_dimension));
  job.height = int(in_range(o.height ? "--height" : "the scene's height (film.height; --height overrides it)",
                            o.height.value_or(scene.film.height), 1, limits.max_dimension));
  const ResolvedRule rule = resolve_rule(scene, o, limits);
  job.spp = uint32_t(rule.spp);
  job.rule = rule.rule;
  job.time_budget_s = rule.time_s;
  job.noise_target = rule.noise;
  const int depth = o.max_depth.value_or(scene.render.max_depth);
  if (depth != -1 && depth < 1) bad("--max-depth", "must be -1 (unbounded) or >= 1", depth);
  job.max_depth = depth;
  job.seed = o.seed.value_or(scene.render.seed);  // every 64-bit value is a seed
  job.tile_size = int(in_range("--tile", o.tile_size.value_or(64), 1, limits.max_tile));
  const int64_t batch =
      o.batch_spp.value_or(job.rule == StopRule::noise ? std::min(kNoiseBatchSpp, job.spp) : 0);
  if (o.batch_spp.has_value()) in_range("--batch", batch, 1, limits.max_spp);
  const JobPlan plan = make_job_plan(job.width, job.height, job.tile_size, job.spp, uint32_t(batch));
  job.batch_spp = plan.batch_spp;
  job.batch_kind = plan.batch_kind;
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
