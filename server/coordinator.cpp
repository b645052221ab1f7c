#include "coordinator.h"

#include <filesystem>
#include <fstream>
#include <limits>
#include <iostream>
#include <sstream>

#include "accum/accumulation_codec.h"
#include "call_trace.h"
#include "farm_error.h"
#include "job/job_options.h"
#include "scene/scene_error.h"
#include "store/integrity.h"
#include "store/job_clients_table.h"
#include "store/migrations.h"
#include "store/units_table.h"
#include "store/workers_table.h"
#include "wire/job_options_wire.h"
#include "wire/scene_bundle.h"
#include "wire/sha256.h"

namespace tessera::server {
namespace {

FarmError invalid(const std::string& message) {
  return FarmError(ErrorCode::invalid_argument, message);
}

FarmError job_not_found(int64_t job_id) {
  return FarmError(ErrorCode::not_found, "no job " + std::to_string(job_id));
}

std::optional<std::string> read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return std::move(ss).str();
}

}  // namespace

Coordinator::Coordinator(const CoordinatorConfig& config, const Clock& clock)
    : clock_(clock),
      db_(config.db_path),
      jobs_(db_),
      workers_(db_),
      leases_(db_, jobs_, clock_, config.lease_ms),
      book_(clock_, config.lease_ms),
      merger_(db_, clock_, config.merge_cache_bytes),
      output_(config.output_dir, config.output_opener),
      limits_(config.limits),
      nan_report_fraction_(config.nan_report_fraction),
      retention_days_(config.retention_days),
      before_upload_commit_(config.before_upload_commit) {
  // The whole-file check only after a server stopped without its clean shutdown (a crash, a
  // kill): a clean restart reads no page beyond the header, whatever the store's size. It runs
  // beside the server, not before it: SQLite recovers from a process crash by itself (WAL), and
  // the check, which reads the whole file (tens of seconds on a store of hundreds of MB), guards
  // against a damaged disk or file, which it reports when it finds it.
  // A store this start creates (no migration applied yet) has nothing to check.
  const bool clean = take_clean_shutdown_mark(db_, config.db_path);
  const bool created = schema_version(db_) == 0;
  migrate(db_, clock_.now_unix_ms());
  leases_.set_health_policy(config.health);
  book_.set_health_policy(config.health);
  // The lease book: each unfinished job as stored (resume() revokes the stored leases in both).
  // Workers are learnt at registration, or at their first call after a start (touch_in_memory):
  // start-up reads no worker row.
  for (int64_t id : jobs_.unfinished()) reload_job(id);
  if (!clean && !created && config.db_path != ":memory:") {
    std::cerr << "tessera-server: " << config.db_path
              << " was not closed by a clean shutdown: checking it (PRAGMA quick_check) in the"
                 " background while serving"
              << std::endl;
    const auto began = std::chrono::steady_clock::now();
    check_ = std::make_unique<BackgroundIntegrityCheck>(
        config.db_path, [this, began, path = config.db_path](IntegrityState state,
                                                             const std::string& message) {
          const double s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
          if (state == IntegrityState::damaged) {
            store_damaged(message);
          } else if (state == IntegrityState::ok) {
            std::cerr << "tessera-server: " << path << ": check passed (" << s << " s)"
                      << std::endl;
          } else if (!message.empty()) {
            std::cerr << "tessera-server: warning: " << path << ": " << message
                      << " (the next start checks again)" << std::endl;
          }
        });
  }
}

bool Coordinator::checkpoint() {
  // A check that ends early (or found damage) leaves no mark: the next start checks again.
  bool checked = true;
  if (check_) {
    check_->stop();
    checked = check_->state() == IntegrityState::ok;
  }
  StoreLock lock(*this);
  if (checked) leave_clean_shutdown_mark(db_);
  return checkpoint_wal(db_);
}

void Coordinator::store_damaged(const std::string& message) {
  std::cerr << "tessera-server: ERROR: " << message
            << "; no more leases (uploads of leased units still commit); stop the server"
            << std::endl;
  changes_.stop();  // LeaseUnit answers "no work", long polls and watches end, /readyz fails
  work_.stop();
  std::lock_guard lock(damage_mu_);  // held while the observer runs: see set_damage_observer
  damage_ = message;
  if (damage_observer_) damage_observer_(message);
}

std::optional<IntegrityState> Coordinator::store_check() const {
  if (!check_) return std::nullopt;
  return check_->state();
}

std::optional<double> Coordinator::store_check_progress() const {
  if (!check_) return std::nullopt;
  return check_->progress();
}

std::optional<IntegrityState> Coordinator::wait_for_store_check() const {
  if (!check_) return std::nullopt;
  return check_->wait();
}

std::string Coordinator::store_damage() const {
  std::lock_guard lock(damage_mu_);
  return damage_;
}

void Coordinator::set_damage_observer(std::function<void(const std::string&)> observer) {
  std::lock_guard lock(damage_mu_);
  damage_observer_ = std::move(observer);
  if (!damage_.empty() && damage_observer_) damage_observer_(damage_);
}

StoreCounters Coordinator::store_counters() {
  std::lock_guard lock(mu_);  // no flush: reading the counters runs no statement
  return db_.counters();
}

int Coordinator::resume() {
  // Start-up reads the leased units (by their partial index), one row per job and index probes:
  // no other unit row and no tile (BENCHMARKS.md, "Server start-up time").
  std::vector<int64_t> unfinished;
  {
    StoreLock lock(*this);
    leases_.revoke_all();
    book_.revoke_all();  // the same in the book, loaded by the constructor
    unfinished = jobs_.unfinished();
  }
  for (int64_t id : unfinished) {
    bool complete = false;
    {
      StoreLock lock(*this);
      complete = !units_left(db_, id);
    }
    // finish_job checks the job is running; a queued job has units left anyway.
    if (complete) finish_job(id);
  }
  // Done jobs whose output could not be written (a full disk) get their files now.
  std::vector<DoneOutput> done;
  {
    StoreLock lock(*this);
    done = jobs_.done_outputs();
  }
  for (const DoneOutput& d : done) {
    if (std::filesystem::exists(d.exr) && std::filesystem::exists(d.png)) continue;
    std::optional<JobRecord> record;
    {
      StoreLock lock(*this);
      record = jobs_.get(d.job_id);
    }
    if (record) rewrite_missing_output(*record);
  }
  notify_changed(true);
  return int(unfinished.size());
}

JobRecord Coordinator::submit(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                              int priority, const std::string& client) {
  check_bundle_limits(bundle, limits_);
  wire::BundleContents contents;
  try {
    contents = wire::bundle_from_proto(bundle);
  } catch (const wire::BundleError& e) {
    throw invalid(e.what());
  }
  check_declared_triangles(contents, limits_);
  Scene scene;
  try {
    scene = wire::parse_bundle_scene(contents);
    wire::check_scene_images(scene);
  } catch (const SceneError& e) {
    throw invalid(e.what());
  } catch (const std::exception& e) {
    throw invalid(contents.scene_file + ": " + e.what());
  }
  check_scene_triangles(scene, limits_);
  JobOptions resolved;
  try {
    resolved = resolve_job_options(scene, wire::overrides_from_proto(options), limits_.job);
  } catch (const std::invalid_argument& e) {
    throw invalid(e.what());
  }
  check_pixel_count(resolved, limits_);
  check_unit_count(resolved, limits_);
  NewJob job;
  job.bundle_bytes = wire::canonical_bytes(contents);
  job.bundle_sha256 = wire::sha256_hex(job.bundle_bytes);
  job.scene_file = contents.scene_file;
  job.options = resolved;
  job.priority = priority;
  JobRecord record;
  {
    StoreLock lock(*this);
    const uint64_t quota = limits_.max_queued_jobs_per_client;
    if (quota > 0) {
      const uint64_t active = JobClientsTable(db_).unfinished_of(client);
      if (active >= quota) {
        throw FarmError(ErrorCode::resource_exhausted,
                        "client " + client + " already has " + std::to_string(active) +
                            " unfinished job(s), the farm's limit (server flag --max-queued-jobs);"
                            " wait for one to finish or cancel one");
      }
    }
    const int64_t id = jobs_.create(job, clock_.now_unix_ms());
    JobClientsTable(db_).add(id, client);
    record = *jobs_.get(id);
    reload_job(id);
  }
  notify_changed(true);
  return record;
}

JobRecord Coordinator::job(int64_t job_id) {
  StoreLock lock(*this);
  std::optional<JobRecord> record = jobs_.get(job_id);
  if (!record) throw job_not_found(job_id);
  record->read_unix_ms = clock_.now_unix_ms();
  return *record;
}

std::vector<JobRecord> Coordinator::jobs(uint32_t limit) {
  StoreLock lock(*this);
  std::vector<JobRecord> out = jobs_.list(limit);
  for (JobRecord& r : out) r.read_unix_ms = clock_.now_unix_ms();
  return out;
}

JobRecord Coordinator::cancel(int64_t job_id) {
  JobRecord record;
  {
    StoreLock lock(*this);
    switch (jobs_.cancel(job_id, clock_.now_unix_ms())) {
      case CancelOutcome::not_found: throw job_not_found(job_id);
      case CancelOutcome::already_final: {
        const JobRecord current = *jobs_.get(job_id);
        throw FarmError(ErrorCode::failed_precondition,
                        "job " + std::to_string(job_id) + " is already " +
                            std::string(to_string(current.state)));
      }
      case CancelOutcome::cancelled: break;
    }
    book_.drop_job(job_id);  // its units and leases were cancelled in the store
    record = *jobs_.get(job_id);
  }
  notify_changed(true);
  return record;
}

void Coordinator::remove(int64_t job_id) {
  std::optional<JobRecord> record;
  {
    StoreLock lock(*this);
    record = jobs_.get(job_id);
    if (!record) throw job_not_found(job_id);
    if (finishing_.contains(job_id)) {
      throw FarmError(ErrorCode::failed_precondition,
                      "job " + std::to_string(job_id) + " is writing its output: try again");
    }
    switch (jobs_.remove(job_id)) {
      case DeleteOutcome::not_found: throw job_not_found(job_id);
      case DeleteOutcome::not_final:
        throw FarmError(ErrorCode::failed_precondition,
                        "job " + std::to_string(job_id) + " is " +
                            std::string(to_string(record->state)) + ": cancel it first");
      case DeleteOutcome::deleted: break;
    }
    merger_.forget_job(job_id);
    book_.drop_job(job_id);
    std::lock_guard rects(tile_rects_mu_);
    tile_rects_.erase(tile_rects_.lower_bound({job_id, 0}),
                      tile_rects_.lower_bound({job_id + 1, 0}));
  }
  // The job is gone from the store: its files are nobody's now.
  for (const std::string& file : {record->output_exr, record->output_png}) {
    std::error_code ec;
    if (!file.empty()) std::filesystem::remove(file, ec);
  }
  notify_changed(true);
}

int Coordinator::apply_retention() {
  std::vector<int64_t> old;
  {
    StoreLock lock(*this);
    const int64_t now = clock_.now_unix_ms();
    if (retention_days_ <= 0 || now - last_retention_unix_ms_ < 60'000) return 0;
    last_retention_unix_ms_ = now;
    old = jobs_.finished_before(now - int64_t(retention_days_ * 86'400'000.0));
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

JobImage Coordinator::image(int64_t job_id, const std::string& format) {
  if (format != "exr" && format != "png") throw invalid("image format must be exr or png");
  JobRecord record;
  {
    StoreLock lock(*this);
    std::optional<JobRecord> found = jobs_.get(job_id);
    if (!found) throw job_not_found(job_id);
    record = std::move(*found);
  }
  JobImage out;
  out.final = record.state == JobState::done;
  out.spp = record.spp_merged;
  out.width = record.options.width;
  out.height = record.options.height;
  if (out.final) {
    const std::string& path = format == "exr" ? record.output_exr : record.output_png;
    if (std::optional<std::string> bytes = read_file(path)) {
      out.bytes = std::move(*bytes);
      return out;
    }
    // The file is missing (it could not be written, or was removed): the merged tiles are still
    // in the store. Write the files again, and encode the answer from the tiles.
    rewrite_missing_output(record);
    if (std::optional<std::string> bytes = read_file(path)) {
      out.bytes = std::move(*bytes);
      return out;
    }
  }
  std::vector<TilePosition> tiles;
  {
    StoreLock lock(*this);
    merger_.checkpoint_job(job_id);  // the merged sums, not just the last checkpoints
    tiles = jobs_.tile_positions(job_id);
  }
  // A row of tiles at a time, as the files are written: tiles merged meanwhile show what they
  // have when their row is read.
  out.bytes = JobOutput::encode(record, tiles, checkpoint_reader(job_id), format);
  return out;
}

std::vector<WorkerRecord> Coordinator::workers() {
  StoreLock lock(*this);
  std::vector<WorkerRecord> list = workers_.list();
  for (WorkerRecord& w : list) w.health_warning = health_warning(w, nan_report_fraction_);
  return list;
}

void Coordinator::report_health(int64_t worker_id) {
  if (reported_workers_.contains(worker_id)) return;
  const std::optional<WorkerRecord> w = workers_.get(worker_id);
  if (!w) return;
  const std::string warning = health_warning(*w, nan_report_fraction_);
  if (warning.empty()) return;
  reported_workers_.insert(worker_id);
  std::cerr << "tessera-server: warning: worker " << worker_id << " (" << w->info.name
            << "): " << warning << std::endl;
}

bool Coordinator::online(const WorkerRecord& worker) const {
  {
    std::lock_guard lock(departed_mu_);
    if (departed_.contains(worker.id)) return false;
  }
  return clock_.now_unix_ms() - worker.last_seen_unix_ms <= 3 * leases_.lease_ms();
}

void Coordinator::deregister(int64_t worker_id) {
  std::lock_guard lock(departed_mu_);
  departed_[worker_id] = calls_begun_.load();
}

int64_t Coordinator::register_worker(const WorkerRegistration& info) {
  int64_t id = 0;
  {
    StoreLock lock(*this);
    id = workers_.register_worker(info, clock_.now_unix_ms());
    book_.add_worker(id);
  }
  notify_changed(true);
  return id;
}

void Coordinator::touch_in_memory(int64_t worker_id, uint64_t call) {
  const int64_t began_ns = call_trace::now_ns();
  {
    std::lock_guard lock(departed_mu_);
    if (const auto it = departed_.find(worker_id); it != departed_.end() && call >= it->second) {
      departed_.erase(it);
    }
  }
  if (!book_.knows_worker(worker_id)) {
    // Its first call since the server started (or an unknown id): the one lease or heartbeat
    // of a worker that asks the store.
    StoreLock lock(*this);
    if (!workers_.get(worker_id)) {
      throw FarmError(ErrorCode::failed_precondition,
                      "no worker " + std::to_string(worker_id) + ": register again");
    }
    book_.add_worker(worker_id);
  }
  book_.touch(worker_id, clock_.now_unix_ms());  // last_seen written by the next flush
  call_trace::record("touch", began_ns, call_trace::now_ns());
}

void Coordinator::flush_leases() {
  const int64_t began_ns = call_trace::now_ns();
  std::vector<LeaseBook::Grant> grants = book_.take_journal();
  std::map<int64_t, int64_t> touches = book_.take_touches();
  if (grants.empty() && touches.empty()) return;
  struct Traced {
    int64_t began;
    size_t grants;
    ~Traced() { call_trace::record("flush", began, call_trace::now_ns(), int64_t(grants)); }
  } traced{began_ns, grants.size()};
  std::vector<std::optional<int64_t>> unit_ids;
  try {
    Transaction tx(db_);
    unit_ids = write_grants(db_, leases_, grants);
    for (const auto& [worker_id, at] : touches) {
      int64_t& written = touched_unix_ms_[worker_id];
      if (at - written < touch_interval_ms()) continue;
      WorkersTable(db_).touch(worker_id, at);  // in this transaction
      written = at;
    }
    tx.commit();
  } catch (...) {
    book_.restore_journal(std::move(grants));
    for (const auto& [worker_id, at] : touches) book_.touch(worker_id, at);
    throw;
  }
  const std::vector<Lease> orphans = book_.recorded(grants, unit_ids);
  if (!orphans.empty()) {
    // Not expected: the book forgot a lease the store took. Back to the queue at once, so that
    // no unit stays leased with nobody to expire it.
    std::cerr << "tessera-server: warning: " << orphans.size()
              << " lease(s) written after the lease book dropped them: requeued" << std::endl;
    for (const Lease& l : leases_.expire(orphans)) reload_job(l.job_id);
  }
}

void Coordinator::reload_job(int64_t job_id) {
  if (std::optional<LeaseBookJob> job = load_lease_book_job(db_, jobs_, job_id)) {
    book_.put_job(std::move(*job));
  } else {
    book_.drop_job(job_id);
  }
}

void Coordinator::touch_or_throw(int64_t worker_id, uint64_t call) {
  {
    std::lock_guard lock(departed_mu_);
    // A call begun after it deregistered: it calls again, online again. A long poll begun
    // before (its worker stopped while it waited) does not count.
    if (const auto it = departed_.find(worker_id); it != departed_.end() && call >= it->second) {
      departed_.erase(it);
    }
  }
  const int64_t now = clock_.now_unix_ms();
  if (const auto it = touched_unix_ms_.find(worker_id);
      it != touched_unix_ms_.end() && now - it->second < touch_interval_ms()) {
    return;  // seen less than touch_interval_ms() ago: last_seen is recent enough
  }
  if (!workers_.touch(worker_id, now)) {
    // FAILED_PRECONDITION, not NOT_FOUND: the worker tells "register again" by the code alone.
    throw FarmError(ErrorCode::failed_precondition,
                    "no worker " + std::to_string(worker_id) + ": register again");
  }
  touched_unix_ms_[worker_id] = now;
}

std::optional<LeasedUnit> Coordinator::lease(int64_t worker_id, std::chrono::milliseconds wait,
                                             const std::function<bool()>& cancelled) {
  std::vector<LeasedUnit> units = lease_units(worker_id, 1, wait, cancelled);
  if (units.empty()) return std::nullopt;
  return std::move(units.front());
}

std::vector<LeasedUnit> Coordinator::lease_units(int64_t worker_id, uint32_t max_units,
                                                 std::chrono::milliseconds wait,
                                                 const std::function<bool()>& cancelled,
                                                 const std::vector<std::string>& delivering) {
  if (delivering.size() > kMaxDelivering) {
    throw invalid("a lease names " + std::to_string(delivering.size()) +
                  " leases as delivering; at most " + std::to_string(kMaxDelivering));
  }
  // From the lease book alone: no store lock, no statement (the grants reach the store with
  // the next store operation: flush_leases).
  const auto deadline = std::chrono::steady_clock::now() + wait;
  const uint64_t call = begin_call();
  for (;;) {
    if (changes_.stopped()) return {};  // shutting down: no new leases
    // Read the version before looking, so a change made while we look wakes the wait below.
    const uint64_t seen = work_.version();
    touch_in_memory(worker_id, call);
    std::vector<LeasedUnit> units = book_.lease_up_to(worker_id, std::max(1u, max_units), delivering);
    if (!units.empty()) {
      notify_changed(false);  // progress (the job may have started); no work for others
      return units;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline || changes_.stopped() || (cancelled && cancelled())) return {};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    const int64_t waited_ns = call_trace::now_ns();
    work_.wait(seen, std::min(left, std::chrono::milliseconds(250)));
    call_trace::record("poll", waited_ns, call_trace::now_ns());
  }
}

std::optional<int64_t> Coordinator::heartbeat(int64_t worker_id, const std::string& lease_id) {
  touch_in_memory(worker_id, begin_call());
  return book_.extend(worker_id, lease_id);
}

std::vector<std::optional<int64_t>> Coordinator::heartbeat_all(
    int64_t worker_id, const std::vector<std::string>& lease_ids) {
  if (lease_ids.size() > kMaxLeasesPerHeartbeat) {
    throw invalid("a heartbeat names " + std::to_string(lease_ids.size()) +
                  " leases; at most " + std::to_string(kMaxLeasesPerHeartbeat) + " per call");
  }
  touch_in_memory(worker_id, begin_call());
  std::vector<std::optional<int64_t>> out;
  out.reserve(lease_ids.size());
  for (const std::string& id : lease_ids) out.push_back(book_.extend(worker_id, id));
  return out;
}

std::string Coordinator::bundle(const std::string& sha256) {
  if (!wire::is_sha256_hex(sha256)) {
    throw invalid("bundle hash must be 64 lowercase hex characters (got \"" + sha256 + "\")");
  }
  StoreLock lock(*this);
  std::optional<std::string> bytes = jobs_.bundle_bytes(sha256);
  if (!bytes) throw FarmError(ErrorCode::not_found, "no bundle " + sha256);
  return std::move(*bytes);
}

std::vector<std::optional<TileRect>> Coordinator::tile_rects(
    const std::vector<UnitResult>& results) {
  std::vector<std::optional<TileRect>> rects(results.size());
  bool missing = false;
  {
    std::lock_guard lock(tile_rects_mu_);
    for (size_t i = 0; i < results.size(); ++i) {
      const auto it = tile_rects_.find({results[i].job_id, results[i].tile});
      if (it != tile_rects_.end()) rects[i] = it->second;
      missing = missing || !rects[i];
    }
  }
  if (!missing) return rects;
  StoreLock lock(*this);
  for (size_t i = 0; i < results.size(); ++i) {
    if (rects[i]) continue;
    rects[i] = jobs_.tile_rect(results[i].job_id, results[i].tile);
    if (!rects[i]) continue;
    std::lock_guard kept(tile_rects_mu_);
    if (tile_rects_.size() >= kTileRectsKept) tile_rects_.clear();
    tile_rects_.emplace(std::pair(results[i].job_id, results[i].tile), *rects[i]);
  }
  return rects;
}

AcceptOutcome Coordinator::upload(const UnitResult& result) {
  return upload_all({result}).front();
}

std::vector<AcceptOutcome> Coordinator::upload_all(const std::vector<UnitResult>& results) {
  if (results.empty()) return {};
  // Names result i in errors when the call carries several.
  const auto which = [&](size_t i) {
    return results.size() > 1 ? "result " + std::to_string(i) + ": " : std::string();
  };
  // The unit's tile bounds what decoding may allocate: the codec sizes its buffers from the
  // result's header, and a few kilobytes of zstd can declare gigabytes (docs/reliability.md,
  // "Known problems"). So the worker and the tiles are looked up first, and a header declaring
  // more pixels than the tile is refused before anything is decompressed.
  // Both from memory, as a lease's check of the worker: no store lock unless the worker or a
  // tile is new to this server.
  std::vector<int64_t> tile_pixels;
  {
    const int64_t asked_ns = call_trace::now_ns();
    touch_in_memory(results.front().worker_id, begin_call());
    const std::vector<std::optional<TileRect>> rects = tile_rects(results);
    call_trace::record("upload_lock", asked_ns, call_trace::now_ns());
    for (size_t i = 0; i < results.size(); ++i) {
      const UnitResult& r = results[i];
      const std::optional<TileRect>& rect = rects[i];
      if (!rect) {
        throw FarmError(ErrorCode::not_found, which(i) + "no unit job " + std::to_string(r.job_id) +
                                                  " tile " + std::to_string(r.tile) + " batch " +
                                                  std::to_string(r.batch));
      }
      tile_pixels.push_back(rect->pixel_count());
    }
  }
  const auto received = std::chrono::steady_clock::now();
  const int64_t decode_ns = call_trace::now_ns();
  std::vector<Accumulation> decoded(results.size());
  std::vector<TileMerger::Upload> uploads;
  for (size_t i = 0; i < results.size(); ++i) {
    try {
      decoded[i] = decode_accumulation(results[i].encoded, tile_pixels[i]);
    } catch (const CodecError& e) {
      throw invalid(which(i) + "result does not decode: " + e.what());
    }
    uploads.push_back({&results[i], &decoded[i]});
  }
  // The worker was checked (and its last call recorded) above; workers are never removed.
  UploadCall call;
  call.uploads = &uploads;
  const int64_t commit_ns = call_trace::now_ns();
  call_trace::record("decode", decode_ns, commit_ns, int64_t(results.size()));
  upload_commits_.run(call);
  call_trace::record("commit_wait", commit_ns, call_trace::now_ns(), int64_t(results.size()));
  if (call.error) std::rethrow_exception(call.error);
  const std::vector<AcceptOutcome>& outcomes = call.outcomes;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - received).count();
  std::set<int64_t> complete;
  bool frees_work = false;
  for (size_t i = 0; i < results.size(); ++i) {
    if (upload_observer_) {
      upload_observer_->record_result(results[i].worker_id, results[i].job_id,
                                      outcomes[i].accepted, outcomes[i].samples, seconds);
    }
    if (outcomes[i].job_complete) complete.insert(results[i].job_id);
    frees_work = frees_work || outcomes[i].frees_work;
  }
  // Progress for watchers; idle workers' long polls only when a merge may have let a unit be
  // leased (a noise tile's lookahead moved): at a job's end every upload used to wake every
  // idle worker's poll for nothing.
  notify_changed(frees_work);
  for (int64_t id : complete) finish_job(id);
  return outcomes;
}

void Coordinator::commit_upload(UploadCall& call) {
  const std::vector<TileMerger::Upload>& uploads = *call.uploads;
  try {
    call.outcomes = merger_.accept_all(uploads);
  } catch (const FarmError& e) {
    call.error = uploads.size() == 1
                     ? std::current_exception()
                     : std::make_exception_ptr(FarmError(
                           e.code(), "one result of the call was refused, none stored: " +
                                         std::string(e.what())));
  } catch (...) {
    call.error = std::current_exception();
  }
}

void Coordinator::commit_uploads(const std::vector<UploadCall*>& calls) {
  // Leases first: this group's transaction starts once no lease or heartbeat waits for mu_, and
  // it ends early, between two calls, when one comes to wait meanwhile: the calls left commit in
  // the next transaction, after the lease. A lease then waits for at most one call's results
  // (at most 64), not for the whole group (up to kResultsPerCommit; BENCHMARKS.md, "Lease
  // latency and capacity").
  if (before_upload_commit_) {
    size_t results = 0;
    for (const UploadCall* c : calls) results += c->uploads->size();
    before_upload_commit_(results);
  }
  const int64_t asked_ns = call_trace::now_ns();
  PriorityMutex::Deferring lock(mu_);
  const int64_t got_ns = call_trace::now_ns();
  struct Traced {
    int64_t asked, got;
    size_t calls;
    ~Traced() {
      call_trace::record("group_lock", asked, got, int64_t(calls));
      call_trace::record("group", got, call_trace::now_ns(), int64_t(calls));
    }
  } traced{asked_ns, got_ns, calls.size()};
  const auto lease_waits = [this] { return mu_.urgent_waiting() > 0; };
  size_t next = 0;  // the first call not committed yet
  while (next < calls.size()) {
    if (next > 0) {
      lock.yield();  // the callers waiting Urgent go first
    }
    // The leases answered so far reach the store before their results (flush_leases).
    try {
      flush_leases();
    } catch (...) {
      for (; next < calls.size(); ++next) calls[next]->error = std::current_exception();
      break;
    }
    if (next + 1 == calls.size()) {
      commit_upload(*calls[next++]);
      break;
    }
    std::vector<TileMerger::Upload> all;
    std::vector<size_t> ends;
    for (size_t c = next; c < calls.size(); ++c) {
      all.insert(all.end(), calls[c]->uploads->begin(), calls[c]->uploads->end());
      ends.push_back(all.size());
    }
    try {
      const std::vector<AcceptOutcome> outcomes = merger_.accept_calls(all, ends, lease_waits);
      size_t used = 0;
      while (used < outcomes.size()) {
        UploadCall* c = calls[next++];
        c->outcomes.assign(outcomes.begin() + ptrdiff_t(used),
                           outcomes.begin() + ptrdiff_t(used + c->uploads->size()));
        used += c->uploads->size();
      }
    } catch (...) {
      // Rolled back: each call left on its own, so that only the call at fault is refused.
      for (; next < calls.size(); ++next) commit_upload(*calls[next]);
    }
  }
  // The lease book follows: accepted (or dropped) leases end; a merge moves its tile's prefix
  // (a noise tile's lookahead) or closes the tile. Still under mu_, so no store operation sees
  // the book behind the store.
  for (const UploadCall* c : calls) {
    if (c->error) continue;
    for (size_t i = 0; i < c->uploads->size(); ++i) {
      const UnitResult& r = *(*c->uploads)[i].result;
      const AcceptOutcome& o = c->outcomes[i];
      if (o.accepted) book_.ended(r.lease_id);
      if (o.tile_next_batch) book_.tile_merged(r.job_id, r.tile, *o.tile_next_batch, o.tile_closed);
    }
  }
  for (const UploadCall* c : calls) {
    if (c->error) continue;
    for (size_t i = 0; i < c->uploads->size(); ++i) {
      // Only NaN/Inf samples can move a worker over the report threshold.
      const TileMerger::Upload& u = (*c->uploads)[i];
      if (c->outcomes[i].accepted && u.decoded->nan_dropped + u.decoded->inf_dropped > 0) {
        report_health(u.result->worker_id);
      }
    }
  }
}

ReleaseOutcome Coordinator::release(int64_t worker_id, const std::string& lease_id,
                                    ReleaseReason reason, const std::string& message) {
  ReleaseOutcome outcome;
  {
    StoreLock lock(*this);
    touch_or_throw(worker_id);
    const std::optional<Lease> held = book_.find(worker_id, lease_id);
    outcome = leases_.release(worker_id, lease_id, reason, message);
    if (held) reload_job(held->job_id);  // its unit queued again, a failure block, or failed
  }
  notify_changed(true);
  return outcome;
}

int Coordinator::expire_leases() {
  int expired = 0;
  std::vector<int64_t> out_of_time;
  {
    StoreLock lock(*this);
    // Expiry is the lease book's (heartbeats extend leases there): its due leases go back to
    // the queue in the store, then in the book.
    expired = expire_due_leases(book_, leases_, clock_.now_unix_ms());
    out_of_time = leases_.enforce_time_budgets();
  }
  if (expired > 0) notify_changed(true);
  for (int64_t id : out_of_time) finish_job(id);
  return expired;
}

void Coordinator::finish_job(int64_t job_id) {
  JobRecord record;
  std::vector<TilePosition> tiles;
  {
    StoreLock lock(*this);
    std::optional<JobRecord> found = jobs_.get(job_id);
    if (!found || found->state != JobState::running || finishing_.contains(job_id)) return;
    // Why it stopped goes into the output's provenance: settle before reading the record.
    if (jobs_.settle(job_id) == StopReason::none) return;
    finishing_.insert(job_id);
    record = std::move(*jobs_.get(job_id));
    merger_.checkpoint_job(job_id);  // the merged sums, not just the last checkpoints
    tiles = jobs_.tile_positions(job_id);
  }
  const int64_t now = clock_.now_unix_ms();
  record.finished_unix_ms = now;
  // Every unit is merged: the job is done whatever happens to its files. A write that fails (a
  // full disk) is logged and retried by the next `get` of the job and at the next start; the
  // merged image stays in the store meanwhile (docs/design.md, "Leases and failures").
  const OutputFiles files = output_.files(record);
  try {
    output_.write(record, tiles, checkpoint_reader(job_id));
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: job " << job_id << " is done but its output was not written: "
              << e.what() << "; the image stays in the store and is written again by the next"
              << " `tessera get " << job_id << "` or server start" << std::endl;
  }
  {
    StoreLock lock(*this);
    finishing_.erase(job_id);
    if (jobs_.finish(job_id, files.exr.string(), files.png.string(), now)) book_.drop_job(job_id);
  }
  notify_changed(true);
}

TileCheckpointReader Coordinator::checkpoint_reader(int64_t job_id) {
  // The store lock for each tile's read only, so that the writer's decoding, resolving and
  // encoding of a large image never hold up leases and uploads.
  return [this, job_id](uint32_t tile) {
    StoreLock lock(*this);
    return jobs_.tile_checkpoint(job_id, tile);
  };
}

void Coordinator::rewrite_missing_output(const JobRecord& record) {
  if (record.state != JobState::done) return;
  if (std::filesystem::exists(record.output_exr) && std::filesystem::exists(record.output_png)) {
    return;
  }
  std::vector<TilePosition> tiles;
  {
    StoreLock lock(*this);
    merger_.checkpoint_job(record.id);
    tiles = jobs_.tile_positions(record.id);
  }
  try {
    output_.write(record, tiles, checkpoint_reader(record.id));
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: job " << record.id << ": writing its output again failed: "
              << e.what() << std::endl;
  }
}

}  // namespace tessera::server
