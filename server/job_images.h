// A job's images: the output files written when its last unit is merged (or its time is up),
// written again when one is missing, and the image a caller asks for, the final file when the
// job is done, else a preview encoded from the merged tiles. Files are decoded, resolved and
// encoded outside the store's lock, which is taken for each tile's read only.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "farm_events.h"
#include "farm_store.h"
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

  JobImages(FarmStore& store, FarmEvents& events, const Clock& clock, JobOutput output,
            CheckpointSums checkpoint_sums)
      : store_(store),
        events_(events),
        clock_(clock),
        output_(std::move(output)),
        checkpoint_sums_(std::move(checkpoint_sums)) {}

  /// Writes the output of a running job whose every unit is merged (or whose time is up) and
  /// marks it done (or failed with the reason). Does nothing for a job that is not running, is
  /// being finished by another call, or is not ready to stop.
  void finish_job(int64_t job_id);
  /// `format` is "exr" or "png". The final output when the job is done, else a preview.
  JobImage image(int64_t job_id, const std::string& format);
  /// At start-up: the done jobs whose output could not be written (a full disk) get their files.
  void rewrite_missing_outputs();
  /// Whether the job's output is being written (a delete waits). Requires the store's lock.
  bool finishing(int64_t job_id);
  /// What a caller is told about `record`'s files: when the last write of them failed, its
  /// reason in output_error and no output paths (the files do not exist); else unchanged.
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
};

}  // namespace tessera::server
