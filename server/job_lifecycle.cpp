#include "job_lifecycle.h"

#include <filesystem>
#include <set>
#include <string>

#include "farm_error.h"
#include "job/job_options.h"
#include "store/job_state.h"
#include "scene/message_text.h"
#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"
#include "store/job_clients_table.h"
#include "store/jobs_table.h"
#include "wire/job_options_wire.h"
#include "wire/scene_bundle.h"
#include "wire/sha256.h"

namespace tessera::server {
namespace {

FarmError job_already_final(int64_t job_id, JobState state) {
  return FarmError(ErrorCode::failed_precondition, "job " + std::to_string(job_id) +
                                                      " is already " +
                                                      std::string(to_string(state)));
}

/// A bundle holds its scene file and the files the scene names, nothing else: bytes no render
/// reads would be stored with the job and sent to every worker. The CLI's bundles are made
/// from the scene's own list (wire::bundle_from_disk); a raw gRPC client's may carry more.
void refuse_files_the_scene_never_names(const wire::BundleContents& contents, const Scene& scene) {
  std::set<std::string> named{contents.scene_file};
  for (const std::string& file : scene.referenced_files) {
    try {
      named.insert(check_bundle_path(file, "referenced file"));  // the bundle's spelling
    } catch (const SceneError&) {
      named.insert(file);  // the reader served it, so it is in the bundle as named
    }
  }
  for (const auto& [path, bytes] : contents.files) {
    if (named.count(path)) continue;
    throw FarmError(ErrorCode::invalid_argument,
                    contents.scene_file + ": the bundle carries \"" + printable(path) +
                        "\", a file the scene never names (a bundle holds the scene file and "
                        "the files it names, nothing else)");
  }
}

}  // namespace

int JobLifecycle::resume() {
  // Start-up reads the leased units (by their partial index), one row per job and index probes:
  // no other unit row and no tile (BENCHMARKS.md, "Server start-up time").
  std::vector<int64_t> unfinished;
  {
    FarmStore::Lock lock(store_);
    store_.leases().revoke_all();
    store_.book().revoke_all();  // the same in the book, loaded by FarmStore's constructor
    unfinished = store_.jobs().unfinished();
  }
  for (int64_t id : unfinished) {
    bool complete = false;
    {
      FarmStore::Lock lock(store_);
      complete = !units_left(store_.db(), id);
    }
    // finish_job checks the job is running; a queued job has units left anyway.
    if (complete) images_.finish_job(id);
  }
  // Done jobs whose output could not be written (a full disk) get their files now.
  images_.rewrite_missing_outputs();
  events_.notify(true);
  return int(unfinished.size());
}

NewJob JobLifecycle::validated(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                               int priority) {
  check_bundle_limits(bundle, limits_);
  wire::BundleContents contents;
  try {
    contents = wire::bundle_from_proto(bundle);
  } catch (const wire::BundleError& e) {
    throw invalid_argument(e.what());
  }
  check_declared_triangles(contents, limits_);
  Scene scene;
  try {
    scene = wire::parse_bundle_scene(contents);
    wire::check_scene_images(scene);
  } catch (const SceneError& e) {
    throw invalid_argument(e.what());
  } catch (const std::exception& e) {
    throw invalid_argument(contents.scene_file + ": " + e.what());
  }
  check_scene_triangles(scene, limits_);
  refuse_files_the_scene_never_names(contents, scene);
  JobOptions resolved;
  try {
    resolved = resolve_job_options(scene, wire::overrides_from_proto(options), limits_.job);
  } catch (const std::invalid_argument& e) {
    throw invalid_argument(e.what());
  }
  check_pixel_count(resolved, limits_);
  check_unit_count(resolved, limits_);
  check_unit_samples(resolved, limits_);
  NewJob job;
  job.bundle_bytes = wire::canonical_bytes(contents);
  job.bundle_sha256 = wire::sha256_hex(job.bundle_bytes);
  job.scene_file = contents.scene_file;
  job.options = resolved;
  job.priority = priority;
  job.any_build = options.has_any_build() && options.any_build();
  job.verify_rate = options.has_verify_rate() ? options.verify_rate() : 0.0;
  if (!(job.verify_rate >= 0.0 && job.verify_rate <= 1.0)) {
    throw invalid_argument("verify rate must be in [0, 1] (0: no spot checks); got " +
                           std::to_string(options.verify_rate()));
  }
  job.denoise = options.has_denoise() && options.denoise();
  job.guides = job.denoise && options.has_guides() && options.guides();
  if (options.guides() && !job.denoise) throw invalid_argument("--guides needs --denoise");
  if (job.denoise) images_.check_denoise(resolved.width, resolved.height);
  return job;
}

void JobLifecycle::check_quota(const std::string& client) {
  const uint64_t quota = limits_.max_queued_jobs_per_client;
  if (quota == 0) return;
  const uint64_t active = JobClientsTable(store_.db()).unfinished_of(client);
  if (active >= quota) {
    throw FarmError(ErrorCode::resource_exhausted,
                    "client " + client + " already has " + std::to_string(active) +
                        " unfinished job(s), the farm's limit (server flag --max-queued-jobs);"
                        " wait for one to finish or cancel one");
  }
}

JobRecord JobLifecycle::submit(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                               int priority, const std::string& client) {
  const NewJob job = validated(bundle, options, priority);
  JobRecord record;
  {
    FarmStore::Lock lock(store_);
    check_quota(client);
    const int64_t id = store_.jobs().create(job, clock_.now_unix_ms());
    JobClientsTable(store_.db()).add(id, client);
    record = *store_.jobs().get(id);
    store_.reload_job(id);
  }
  events_.notify(true);
  return record;
}

JobRecord JobLifecycle::job(int64_t job_id) {
  FarmStore::ReadLock lock(store_);
  std::optional<JobRecord> record = store_.jobs().get(job_id);
  if (!record) throw job_not_found(job_id);
  record->read_unix_ms = clock_.now_unix_ms();
  images_.describe_output(*record);
  return *record;
}

JobPage JobLifecycle::jobs(const JobQuery& query) {
  FarmStore::ReadLock lock(store_);
  JobPage out = store_.jobs().list(query);
  for (JobRecord& r : out.jobs) {
    r.read_unix_ms = clock_.now_unix_ms();
    images_.describe_output(r);
  }
  return out;
}

std::string JobLifecycle::bundle(const std::string& sha256) {
  if (!wire::is_sha256_hex(sha256)) {
    throw invalid_argument("bundle hash must be 64 lowercase hex characters (got \"" + sha256 +
                           "\")");
  }
  FarmStore::ReadLock lock(store_);
  std::optional<std::string> bytes = store_.jobs().bundle_bytes(sha256);
  if (!bytes) throw FarmError(ErrorCode::not_found, "no bundle " + sha256);
  return std::move(*bytes);
}

JobRecord JobLifecycle::cancel(int64_t job_id) {
  JobRecord record;
  {
    FarmStore::Lock lock(store_);
    JobStore& jobs = store_.jobs();
    switch (jobs.cancel(job_id, clock_.now_unix_ms())) {
      case CancelOutcome::not_found: throw job_not_found(job_id);
      case CancelOutcome::already_final: throw job_already_final(job_id, jobs.get(job_id)->state);
      case CancelOutcome::cancelled: break;
    }
    store_.book().drop_job(job_id);  // its units and leases were cancelled in the store
    record = *jobs.get(job_id);
  }
  events_.notify(true);
  return record;
}

void JobLifecycle::remove(int64_t job_id) {
  std::optional<JobRecord> record;
  {
    FarmStore::Lock lock(store_);
    record = store_.jobs().get(job_id);
    if (!record) throw job_not_found(job_id);
    if (images_.finishing(job_id)) {
      throw FarmError(ErrorCode::failed_precondition,
                      "job " + std::to_string(job_id) + " is writing its output: try again");
    }
    switch (store_.jobs().remove(job_id)) {
      case DeleteOutcome::not_found: throw job_not_found(job_id);
      case DeleteOutcome::not_final:
        throw FarmError(ErrorCode::failed_precondition,
                        "job " + std::to_string(job_id) + " is " +
                            std::string(to_string(record->state)) + ": cancel it first");
      case DeleteOutcome::deleted: break;
    }
    intake_.forget_job(job_id);
    images_.describe_output(*record);  // its denoised files too
    images_.forget(job_id);
    store_.book().drop_job(job_id);
  }
  // The job is gone from the store: its files are nobody's now.
  for (const std::string& file : {record->output_exr, record->output_png,
                                   record->output_denoised_exr, record->output_denoised_png}) {
    std::error_code ec;
    if (!file.empty()) std::filesystem::remove(file, ec);
  }
  events_.notify(true);
}

int JobLifecycle::apply_retention() {
  std::vector<int64_t> old;
  {
    FarmStore::Lock lock(store_);
    const int64_t now = clock_.now_unix_ms();
    if (retention_days_ <= 0 || now - last_retention_unix_ms_ < 60'000) return 0;
    last_retention_unix_ms_ = now;
    old = store_.jobs().finished_before(now - int64_t(retention_days_ * 86'400'000.0));
  }
  int deleted = 0;
  for (int64_t id : old) {
    try {
      remove(id);
      ++deleted;
    } catch (const FarmError&) {
      // Deleted meanwhile (by hand): nothing to do.
    }
  }
  return deleted;
}

JobRecord JobLifecycle::set_priority(int64_t job_id, int priority) {
  JobRecord record;
  {
    FarmStore::Lock lock(store_);
    // Compare-and-set on the state: a job that ends meanwhile keeps its recorded priority.
    const bool changed = JobsTable(store_.db()).set_priority(job_id, priority);
    std::optional<JobRecord> found = store_.jobs().get(job_id);
    if (!found) throw job_not_found(job_id);
    if (!changed) throw job_already_final(job_id, found->state);
    store_.book().set_priority(job_id, priority);
    record = std::move(*found);
  }
  events_.notify(true);
  return record;
}

}  // namespace tessera::server
