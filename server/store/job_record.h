// What the store keeps of a job and its tiles, as the server's policy reads them: the records
// store/jobs_table.h and store/tiles_table.h return, and what a submit writes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accum/tile_rect.h"
#include "job/job_options.h"
#include "job/stopping_rule.h"
#include "job/tile_summary.h"
#include "store/job_state.h"

namespace tessera::server {

/// Counters of a job (proto JobCounters documents each).
struct JobCounters {
  uint32_t units_done = 0;
  uint32_t units_leased = 0;
  uint32_t results_merged = 0;
  uint32_t results_dropped = 0;
  uint32_t leases_expired = 0;
  uint32_t units_released = 0;
  uint64_t samples_merged = 0;  ///< pixel samples merged: sum over merged units of pixels * spp
  uint64_t nan_dropped = 0;
  uint64_t inf_dropped = 0;
  uint32_t units_skipped = 0;   ///< units the stopping rule made unneeded (UnitEvent::skip)
  uint32_t results_wasted = 0;  ///< accepted results never merged (their tile had finished)
};

struct JobRecord {
  int64_t id = 0;
  JobState state = JobState::queued;
  int priority = 0;
  std::string bundle_sha256;
  std::string scene_file;
  JobOptions options;
  uint32_t tile_count = 0;
  uint32_t batch_count = 0;
  uint32_t units_total = 0;
  JobCounters counters;
  int64_t submitted_unix_ms = 0, started_unix_ms = 0, finished_unix_ms = 0;
  std::string error;
  std::string output_exr, output_png;
  /// Why a done job's output files could not be written (JobImages::describe_output), "" when
  /// they were or are not due yet; output_exr and output_png are empty meanwhile. Not stored:
  /// known from the last write, at the finish, a `get` or the server's start.
  std::string output_error;
  uint32_t spp_merged = 0;           ///< minimum over tiles of samples per pixel merged
  TileSummary reached;               ///< spp and estimated error over tiles
  uint32_t tiles_finished = 0;       ///< tiles the stopping rule gives no more batches
  StopReason stop_reason = StopReason::none;  ///< set when the job ends (cancelled or done)
  int64_t budget_reached_unix_ms = 0;  ///< time rule: when leasing stopped (0 = not yet)
  bool complete = false;             ///< no unit queued or leased: ready to finish
  int64_t read_unix_ms = 0;          ///< when the record was read (for a running job's wall time)
  std::vector<std::string> isas;     ///< distinct ISAs of accepted results, sorted
  std::vector<std::string> versions; ///< distinct renderer versions of accepted results, sorted
  bool any_build = false;  ///< submitted with --any-build: leased to workers of every build
  /// The renderer build every lease of the job goes to (its first lease's worker's); nullopt
  /// before its first lease, and always for an any_build job.
  std::optional<std::string> pinned_build;
  /// Filled by the coordinator: pinned, not final, and no online worker is of its build.
  bool waiting_for_build = false;
  double verify_rate = 0;  ///< spot checks' sampled fraction of units (0: none)
  /// Filled by the coordinator (SpotChecks, since the server started): units checked and
  /// agreed, units merged without the check they were due.
  uint64_t units_checked = 0, units_unverified = 0;
  bool denoise = false;  ///< --denoise: denoised files beside the raw ones (server/job_denoise.h)
  bool guides = false;   ///< --guides: the raw EXR holds the denoiser's guides as channels
  /// Filled by the coordinator for a done denoise job: its denoised files once written, or why
  /// they were not. Not stored: the files' existence is the state.
  std::string output_denoised_exr, output_denoised_png, denoise_error;

  /// Samples merged over samples asked, in [0, 1]; exactly 1 when every unit is merged. For
  /// `noise` and `time` jobs, units settled (done or skipped) over units (a time job: at least
  /// the share of its budget used by read_unix_ms), below 1 until done.
  double progress() const;
  /// Seconds from the first lease to the end, or to read_unix_ms while running; 0 before.
  double wall_time_s() const;
};

/// A tile's merged state as stored.
struct TileRecord {
  uint32_t tile = 0;
  TileRect rect;
  uint32_t next_batch = 0;    ///< batches [0, next_batch) are merged
  uint32_t spp = 0;           ///< samples per pixel merged: the schedule's end of next_batch - 1
  std::string accumulation;   ///< encode_accumulation bytes; empty = nothing merged yet
  double error = 0;           ///< estimated relative error of the merged tile (TileProgress)
  StopReason finished = StopReason::none;  ///< the verdict that closed the tile; none = open
};

/// What a lease needs of its job: the resolved options and the bundle.
struct JobSpec {
  JobOptions options;
  std::string bundle_sha256;
  /// The job denoises: its units over the guides' first samples render the guides too.
  bool guides = false;
};

/// Where a done job's output files are.
struct DoneOutput {
  int64_t job_id = 0;
  std::string exr, png;
  bool denoise = false;  ///< its denoised files are due too
};

struct NewJob {
  std::string bundle_sha256;
  std::string scene_file;
  std::string bundle_bytes;  ///< canonical serialization, stored once per hash
  JobOptions options;
  int priority = 0;
  bool any_build = false;  ///< --any-build: never pinned to one renderer build
  double verify_rate = 0;  ///< --verify: spot checks' sampled fraction of units
  bool denoise = false;    ///< --denoise
  bool guides = false;     ///< --guides (with denoise)
};

}  // namespace tessera::server
