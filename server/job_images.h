// A job's images: the output files written when its last unit is merged (or its time is up),
// written again when one is missing, and the image a caller asks for, the final file when the
// job is done, else a preview encoded from the merged tiles. Files are decoded, resolved and
// encoded outside the store's lock, which is taken for each tile's read only.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "farm_events.h"
#include "farm_store.h"
#include "job_denoise.h"
#include "job_output.h"
#include "store/job_record.h"

namespace tessera::server {

struct JobImage {
  std::string bytes;
  bool final = false;
  uint32_t spp = 0;
  int width = 0, height = 0;
};

class JobImages {
 public:
  /// Writes every tile of the job whose sum is not all in its checkpoint as its checkpoint
  /// (TileMerger::checkpoint_job); called under the store's lock before the tiles are read.
  using CheckpointSums = std::function<void(int64_t job_id)>;

  /// `denoise` null: jobs asking for denoise are refused (JobDenoise::check_submit).
  JobImages(FarmStore& store, FarmEvents& events, const Clock& clock, JobOutput output,
            CheckpointSums checkpoint_sums, std::shared_ptr<JobDenoise> denoise = nullptr)
      : store_(store),
        events_(events),
        clock_(clock),
        output_(std::move(output)),
        checkpoint_sums_(std::move(checkpoint_sums)),
        denoise_(std::move(denoise)) {}

  /// At submit, for a job asking for denoise: throws FarmError when this server cannot
  /// denoise it (JobDenoise::check_submit).
  void check_denoise(int width, int height) const;

  /// Writes the output of a running job whose every unit is merged (or whose time is up) and
  /// marks it done (or failed with the reason). Does nothing for a job that is not running, is
  /// being finished by another call, or is not ready to stop.
  void finish_job(int64_t job_id);
  /// `format` is "exr" or "png". The final output when the job is done, else a preview.
  /// `denoised` (a denoise job's only, else FarmError failed_precondition): the denoised file
  /// when done, else the merged tiles so far denoised now.
  JobImage image(int64_t job_id, const std::string& format, bool denoised = false);
  /// At start-up: the done jobs whose output could not be written (a full disk) get their files.
  void rewrite_missing_outputs();
  /// Whether the job's output is being written (a delete waits). Requires the store's lock.
  bool finishing(int64_t job_id);
  /// What a caller is told about `record`'s files: when the last write of them failed, its
  /// reason in output_error and no output paths (the files do not exist); else unchanged. A
  /// done denoise job's denoised files, when they exist, or why they were not written.
  void describe_output(JobRecord& record);
  /// Forgets a deleted job's output error.
  void forget(int64_t job_id);

 private:
  /// Writes a done job's output files again when one is missing (a full disk when it finished,
  /// or a file removed since). Failures are logged and kept for describe_output: the image stays
  /// in the store.
  void rewrite_missing_output(const JobRecord& record);
  /// Writes the job's files; returns "" or why they were not written (logged as `context`),
  /// remembered for describe_output until a write succeeds.
  std::string write_output(const JobRecord& record, const std::vector<TilePosition>& tiles,
                           const std::string& context);
  /// Every tile's position, with the merged sums checkpointed first. Takes the store's lock.
  /// `preview`: when the store cannot write the checkpoints (a full disk), each tile as of its
  /// last checkpoint rather than an error; files are never written from that.
  std::vector<TilePosition> checkpointed_tiles(int64_t job_id, bool preview = false);
  /// Reads a job's tile checkpoints for JobOutput::write, each under the store's lock.
  TileCheckpointReader checkpoint_reader(int64_t job_id);
  /// Reads a denoise job's merged guides of each of `tiles` (merge_tile_guides), each tile's
  /// rows under the store's lock and merged outside it.
  TileGuideReader guide_reader(const JobRecord& record, std::vector<TilePosition> tiles);
  /// A denoise job's merged image (and its guides, when every tile has them) denoised.
  JobDenoise::Denoised denoised(const JobRecord& record, const std::vector<TilePosition>& tiles);
  /// Writes a done denoise job's denoised files; a failure is logged and remembered for
  /// describe_output until a write succeeds.
  void write_denoised(const JobRecord& record, const std::vector<TilePosition>& tiles);
  /// The denoised image a caller asks for (image() with `denoised`).
  void denoised_image(const JobRecord& record, const std::string& format, JobImage& out);

  FarmStore& store_;
  FarmEvents& events_;
  const Clock& clock_;
  JobOutput output_;
  CheckpointSums checkpoint_sums_;
  /// Jobs whose output is being written; taken inside the store's lock, so that a delete sees
  /// a finish that has begun.
  std::mutex finishing_mu_;
  std::set<int64_t> finishing_;  ///< guarded by finishing_mu_
  /// Done jobs whose last output write failed, and why; guarded by finishing_mu_.
  std::map<int64_t, std::string> output_errors_;
  std::shared_ptr<JobDenoise> denoise_;
  /// Done denoise jobs whose last denoised write failed, and why; guarded by finishing_mu_.
  std::map<int64_t, std::string> denoise_errors_;
};

}  // namespace tessera::server
