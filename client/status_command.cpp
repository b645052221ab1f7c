// `tessera status JOB`: a job's state, options, counters, times and what it reached.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <memory>

#include "build_text.h"
#include "command_support.h"
#include "job/batch_schedule.h"
#include "job/tile_summary.h"
#include "json_view.h"

namespace tessera::client {
namespace {

/// A time of day in local time, "-" for none.
std::string local_time_text(int64_t unix_ms) {
  if (unix_ms <= 0) return "-";
  const std::time_t t = std::time_t(unix_ms / 1000);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  return buf;
}

/// The batch schedule: "batch 64", or the first batches of a progressive one from the schedule
/// itself (core/job/batch_schedule.h): "batches 1, 1, 2, 4, 8, ... 1024 spp".
std::string batches_text(const v1::ResolvedJobOptions& o) {
  const BatchSchedule schedule{
      batch_kind_from_string(o.batch_schedule()).value_or(BatchKind::fixed), o.batch_spp(),
      o.spp()};
  if (schedule.kind == BatchKind::fixed) return "batch " + std::to_string(o.batch_spp());
  std::string text = "batches";
  const uint32_t shown = std::min(schedule.count(), 5u);
  for (uint32_t b = 0; b < shown; ++b) {
    text += (b ? ", " : " ") + std::to_string(schedule.end(b) - schedule.begin(b));
  }
  if (schedule.count() > shown) text += ", ... " + std::to_string(o.batch_spp());
  return text + " spp";
}

/// The "reached" line: the stop reason, spp per tile, the error estimate and the drops.
void print_reached(const v1::JobInfo& job) {
  const auto& c = job.counters();
  const auto& r = job.reached();
  std::printf("  reached   %s%sspp min %u / mean %.1f / max %u, estimated error max %s / mean "
              "%s, %u tiles finished, wall time %.1f s, NaN/Inf dropped %llu\n",
              reason_name(job.stop_reason()).empty() ? "" : "stopped by ",
              reason_name(job.stop_reason()).empty()
                  ? ""
                  : (reason_name(job.stop_reason()) + ": ").c_str(),
              r.spp_min(), r.spp_mean(), r.spp_max(), error_text(r.error_max(), r.spp_max()).c_str(),
              error_text(r.error_mean(), r.spp_max()).c_str(),
              r.tiles_finished(), job.wall_time_s(),
              static_cast<unsigned long long>(c.nan_dropped() + c.inf_dropped()));
}

void print_status(const v1::JobInfo& job) {
  const auto& o = job.options();
  const auto& c = job.counters();
  std::printf("job %llu: %s, %.1f %% \u2014 every tile has at least %u of %u spp, "
              "priority %d\n",
              static_cast<unsigned long long>(job.id()), state_text(job).c_str(),
              100.0 * job.progress(), job.spp_merged(), o.spp(), job.priority());
  std::printf("  scene     %s (bundle sha256 %s)\n", job.scene_file().c_str(),
              job.bundle_sha256().c_str());
  std::printf("  options   %dx%d, %u spp, max depth %d, seed %llu, tile %d, %s%s%s\n",
              o.width(), o.height(), o.spp(), o.max_depth(),
              static_cast<unsigned long long>(o.seed()), o.tile_size(), batches_text(o).c_str(),
              o.isa().empty() ? "" : ", isa ", o.isa().c_str());
  std::printf("  units     %u total, %u done, %u leased, %u merged\n", c.units_total(),
              c.units_done(), c.units_leased(), c.results_merged());
  std::printf("  retries   %u stale results dropped, %u leases expired, %u units handed back\n",
              c.results_dropped(), c.leases_expired(), c.units_released());
  if (job.verify_rate() > 0) {
    std::printf("  checks    %g %% of units and each worker's first: %llu checked, %llu "
                "unverified\n",
                job.verify_rate() * 100.0, static_cast<unsigned long long>(job.units_checked()),
                static_cast<unsigned long long>(job.units_unverified()));
  }
  std::printf("  times     submitted %s, started %s, finished %s\n",
              local_time_text(job.submitted_unix_ms()).c_str(),
              local_time_text(job.started_unix_ms()).c_str(),
              local_time_text(job.finished_unix_ms()).c_str());
  std::printf("  rule      %s\n", rule_text(o).c_str());
  print_reached(job);
  if (c.units_skipped() + c.results_wasted() > 0) {
    std::printf("  skipped   %u units not needed by the rule, %u results wasted\n",
                c.units_skipped(), c.results_wasted());
  }
  std::fputs(renderer_builds_text(job).c_str(), stdout);
  if (!job.error().empty()) std::printf("  error     %s\n", job.error().c_str());
  if (!job.output_error().empty()) {
    std::printf("  error     output not written: %s (the image is in the server's store; `tessera "
                "get %llu` asks the server to write it again)\n",
                job.output_error().c_str(), static_cast<unsigned long long>(job.id()));
  }
  if (!job.output_exr().empty()) {
    std::printf("  output    %s\n            %s\n", job.output_exr().c_str(),
                job.output_png().c_str());
  }
  if (!job.output_denoised_exr().empty()) {
    std::printf("  denoised  %s\n            %s\n", job.output_denoised_exr().c_str(),
                job.output_denoised_png().c_str());
  }
  if (!job.denoise_error().empty()) {
    std::printf("  error     not denoised: %s\n", job.denoise_error().c_str());
  }
}

int status(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    v1::JobInfo job;
    try {
      job = client.get(job_id);
    } catch (const ClientError&) {
      warn_store_damage(client);  // the damage may be why the call failed
      throw;
    }
    warn_store_damage(client);
    if (g.json) {
      std::cout << to_json(job).dump() << std::endl;
    } else {
      print_status(job);
    }
    return 0;
  });
}

}  // namespace

Command add_status_command(CLI::App& app, GlobalOptions& g) {
  const auto job_id = std::make_shared<uint64_t>(0);
  CLI::App* cmd = app.add_subcommand("status", "Show a job");
  add_job_argument(cmd, *job_id);
  add_json_flag(cmd, g);
  return {cmd, [&g, job_id] { return status(g, *job_id); }};
}

}  // namespace tessera::client
