#include "job_images.h"

#include <filesystem>
#include <iostream>

#include "farm_error.h"
#include "store/job_state.h"

namespace tessera::server {
bool JobImages::finishing(int64_t job_id) {
  std::lock_guard lock(finishing_mu_);
  return finishing_.contains(job_id);
}

void JobImages::finish_job(int64_t job_id) {
  JobRecord record;
  std::vector<TilePosition> tiles;
  {
    FarmStore::Lock lock(store_);
    JobStore& jobs = store_.jobs();
    std::optional<JobRecord> found = jobs.get(job_id);
    if (!found || found->state != JobState::running || finishing(job_id)) return;
    // Why it stopped goes into the output's provenance: settle before reading the record.
    if (jobs.settle(job_id) == StopReason::none) return;
    {
      std::lock_guard guard(finishing_mu_);
      finishing_.insert(job_id);
    }
    record = std::move(*jobs.get(job_id));
    checkpoint_sums_(job_id);  // the merged sums, not just the last checkpoints
    tiles = jobs.tile_positions(job_id);
  }
  const int64_t now = clock_.now_unix_ms();
  record.finished_unix_ms = now;
  // Every unit is merged: the job is done whatever happens to its files. A write that fails (a
  // full disk, a folder that cannot be created) is logged, shown with the job (describe_output)
  // and retried by the next `get` of the job and at the next start; the merged image stays in
  // the store meanwhile (docs/design.md, "Leases and failures").
  const OutputFiles files = output_.files(record);
  write_output(record, tiles, "is done but its output was not written");
  if (record.denoise) write_denoised(record, tiles);
  {
    FarmStore::Lock lock(store_);
    {
      std::lock_guard guard(finishing_mu_);
      finishing_.erase(job_id);
    }
    if (store_.jobs().finish(job_id, files.exr.string(), files.png.string(), now)) {
      store_.book().drop_job(job_id);
    }
  }
  events_.notify(true);
}

JobImage JobImages::image(int64_t job_id, const std::string& format, bool denoised) {
  if (format != "exr" && format != "png") throw invalid_argument("image format must be exr or png");
  JobRecord record;
  {
    FarmStore::ReadLock lock(store_);
    std::optional<JobRecord> found = store_.jobs().get(job_id);
    if (!found) throw job_not_found(job_id);
    record = std::move(*found);
  }
  JobImage out;
  out.final = record.state == JobState::done;
  out.spp = record.spp_merged;
  out.width = record.options.width;
  out.height = record.options.height;
  if (denoised) {
    denoised_image(record, format, out);
    return out;
  }
  if (out.final) {
    const std::string& path = format == "exr" ? record.output_exr : record.output_png;
    if (std::optional<std::string> bytes = read_output_file(path)) {
      out.bytes = std::move(*bytes);
      return out;
    }
    // The file is missing (it could not be written, or was removed): the merged tiles are still
    // in the store. Write the files again, and encode the answer from the tiles.
    rewrite_missing_output(record);
    if (std::optional<std::string> bytes = read_output_file(path)) {
      out.bytes = std::move(*bytes);
      return out;
    }
  }
  // A row of tiles at a time, as the files are written: tiles merged meanwhile show what they
  // have when their row is read.
  const std::vector<TilePosition> tiles = checkpointed_tiles(job_id, /*preview=*/true);
  out.bytes = JobOutput::encode(record, tiles, checkpoint_reader(job_id), format,
                                record.guides ? guide_reader(record, tiles) : TileGuideReader{});
  return out;
}

void JobImages::rewrite_missing_outputs() {
  std::vector<DoneOutput> done;
  {
    FarmStore::Lock lock(store_);
    done = store_.jobs().done_outputs();
  }
  for (const DoneOutput& d : done) {
    if (std::filesystem::exists(d.exr) && std::filesystem::exists(d.png) && !d.denoise) continue;
    std::optional<JobRecord> record;
    {
      FarmStore::Lock lock(store_);
      record = store_.jobs().get(d.job_id);
    }
    if (record) rewrite_missing_output(*record);
  }
}

void JobImages::rewrite_missing_output(const JobRecord& record) {
  if (record.state != JobState::done) return;
  const auto both = [](const std::filesystem::path& a, const std::filesystem::path& b) {
    return std::filesystem::exists(a) && std::filesystem::exists(b);
  };
  const bool raw_missing = !both(record.output_exr, record.output_png);
  const OutputFiles denoised = output_.denoised_files(record);
  const bool denoised_missing = record.denoise && !both(denoised.exr, denoised.png);
  if (!raw_missing && !denoised_missing) return;
  const std::vector<TilePosition> tiles = checkpointed_tiles(record.id);
  if (raw_missing) write_output(record, tiles, "writing its output again failed");
  if (denoised_missing) write_denoised(record, tiles);
}

std::string JobImages::write_output(const JobRecord& record, const std::vector<TilePosition>& tiles,
                                    const std::string& context) {
  std::string why;
  try {
    output_.write(record, tiles, checkpoint_reader(record.id),
                  record.guides ? guide_reader(record, tiles) : TileGuideReader{});
  } catch (const std::exception& e) {
    why = e.what();
    if (why.empty()) why = "unknown error";
    std::cerr << "tessera-server: job " << record.id << " " << context << ": " << why
              << "; the image stays in the store and is written again by the next `tessera get "
              << record.id << "` or server start" << std::endl;
  }
  bool was_missing = false;
  {
    std::lock_guard guard(finishing_mu_);
    if (why.empty()) {
      was_missing = output_errors_.erase(record.id) > 0;
    } else {
      output_errors_[record.id] = why;
    }
  }
  if (was_missing) {
    std::cerr << "tessera-server: job " << record.id << ": its output is written now" << std::endl;
  }
  return why;
}

void JobImages::forget(int64_t job_id) {
  std::lock_guard guard(finishing_mu_);
  output_errors_.erase(job_id);
  denoise_errors_.erase(job_id);
}

void JobImages::describe_output(JobRecord& record) {
  std::lock_guard guard(finishing_mu_);
  if (record.denoise && record.state == JobState::done) {
    const OutputFiles denoised = output_.denoised_files(record);
    if (std::filesystem::exists(denoised.exr)) record.output_denoised_exr = denoised.exr.string();
    if (std::filesystem::exists(denoised.png)) record.output_denoised_png = denoised.png.string();
    if (const auto it = denoise_errors_.find(record.id); it != denoise_errors_.end()) {
      record.denoise_error = it->second;
    }
  }
  const auto it = output_errors_.find(record.id);
  if (it == output_errors_.end() || record.state != JobState::done) return;
  record.output_error = it->second;
  record.output_exr.clear();  // no paths to files that do not exist
  record.output_png.clear();
}

std::vector<TilePosition> JobImages::checkpointed_tiles(int64_t job_id, bool preview) {
  if (!preview) {
    FarmStore::Lock lock(store_);
    checkpoint_sums_(job_id);  // the merged sums, not just the last checkpoints
    return store_.jobs().tile_positions(job_id);
  }
  FarmStore::ReadLock lock(store_);
  try {
    checkpoint_sums_(job_id);
  } catch (const SqliteError&) {
    // The store cannot write: the preview shows each tile as of its last checkpoint.
  }
  return store_.jobs().tile_positions(job_id);
}

TileCheckpointReader JobImages::checkpoint_reader(int64_t job_id) {
  // The store's lock for each tile's read only, so that the writer's decoding, resolving and
  // encoding of a large image never hold up leases and uploads.
  return [this, job_id](uint32_t tile) {
    FarmStore::ReadLock lock(store_);
    return store_.jobs().tile_checkpoint(job_id, tile);
  };
}

}  // namespace tessera::server
