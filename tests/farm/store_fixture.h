// A migrated :memory: store with the farm's components over a fake clock, and helpers that make
// jobs, workers and results without scenes or a renderer.
#pragma once

#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "fake_clock.h"
#include "job_store.h"
#include "lease_book.h"
#include "lease_table.h"
#include "store/migrations.h"
#include "store/sqlite.h"
#include "tessera/v1/job.pb.h"
#include "tile_merger.h"
#include "worker_registry.h"

namespace tessera::server::testing {

/// The farm tests' small scene (data/tiny.json) as a bundle whose scene file is "scene.json".
inline v1::SceneBundle tiny_bundle() {
  std::ifstream in(std::string(TESSERA_TEST_DATA_DIR) + "/tiny.json");
  v1::SceneBundle bundle;
  bundle.set_scene_file("scene.json");
  auto* file = bundle.add_files();
  file->set_path("scene.json");
  file->set_data(std::string(std::istreambuf_iterator<char>(in), {}));
  return bundle;
}

/// A 32x32 job in 8x8 tiles (16 tiles) of 4 batches of 1 spp: 64 units of 64 samples.
inline v1::JobRequestOptions small_units() {
  v1::JobRequestOptions options;
  options.set_width(32);
  options.set_height(32);
  options.set_tile_size(8);
  options.set_spp(4);
  options.set_batch_spp(1);
  return options;
}

/// The upload of `acc` under `lease`, as the lease's worker would send it.
inline UnitResult result_for(const Lease& lease, const Accumulation& acc) {
  UnitResult r;
  r.worker_id = lease.worker_id;
  r.lease_id = lease.lease_id;
  r.job_id = lease.job_id;
  r.tile = lease.tile;
  r.batch = lease.batch;
  r.encoded = encode_accumulation(acc);
  r.isa = "avx2";
  return r;
}

/// Leases as the server leases them (Coordinator::lease_units, then flush_leases): picked by
/// the lease book's scheduling policy (server/scheduler.h) and written to the store at once.
/// The book reads every unfinished job again from the store before each call, as the
/// coordinator's reload_job does at the events it cannot follow alone, so that a test may change
/// the store directly (cancel, release, merge, skip) between calls.
class BookLeaser {
 public:
  BookLeaser(Database& db, JobStore& jobs, LeaseTable& leases, const Clock& clock,
             LeaseBook::IdSource ids = random_lease_id)
      : db_(db), jobs_(jobs), leases_(leases), clock_(clock),
        book_(clock, leases.lease_ms(), std::move(ids)) {}

  /// Every lease the worker holds and new ones up to `max_units` (LeaseBook::lease_up_to), as
  /// written to the store (unit ids known).
  std::vector<Lease> lease_up_to(int64_t worker_id, uint32_t max_units) {
    sync();
    const std::vector<LeasedUnit> units = book_.lease_up_to(worker_id, max_units);
    std::vector<LeaseBook::Grant> grants = book_.take_journal();
    if (!grants.empty()) {
      Transaction tx(db_);
      const std::vector<std::optional<int64_t>> ids = write_grants(db_, leases_, grants);
      tx.commit();
      book_.recorded(grants, ids);
    }
    std::vector<Lease> out;
    for (const LeasedUnit& u : units) {
      if (const std::optional<Lease> l = book_.find(worker_id, u.lease.lease_id)) out.push_back(*l);
    }
    return out;
  }
  /// One lease: the first the worker holds, or a new one; nullopt when there is no work.
  std::optional<Lease> lease_next(int64_t worker_id) {
    const std::vector<Lease> leases = lease_up_to(worker_id, 1);
    if (leases.empty()) return std::nullopt;
    return leases.front();
  }
  /// A heartbeat (Coordinator::heartbeat): the lease's new expiry, nullopt when not current.
  std::optional<int64_t> heartbeat(int64_t worker_id, const std::string& lease_id) {
    sync();
    return book_.extend(worker_id, lease_id);
  }
  /// The leases due now back to the queue (Coordinator::expire_leases); how many.
  int expire_due() {
    sync();
    return expire_due_leases(book_, leases_, clock_.now_unix_ms());
  }
  LeaseBook& book() { return book_; }

 private:
  void sync() {
    book_.set_health_policy(leases_.health_policy());
    std::set<int64_t> live;
    for (const int64_t id : jobs_.unfinished()) {
      live.insert(id);
      if (std::optional<LeaseBookJob> job = load_lease_book_job(db_, jobs_, id)) {
        book_.put_job(std::move(*job));
      } else {
        book_.drop_job(id);
      }
    }
    for (const int64_t id : known_) {
      if (!live.contains(id)) book_.drop_job(id);
    }
    known_ = std::move(live);
  }

  Database& db_;
  JobStore& jobs_;
  LeaseTable& leases_;
  const Clock& clock_;
  LeaseBook book_;
  std::set<int64_t> known_;
};

struct StoreFixture {
  static constexpr int64_t kLeaseMs = 10'000;

  FakeClock clock;
  Database db;
  JobStore jobs{db};
  WorkerRegistry workers{db};
  LeaseTable leases{db, jobs, clock, kLeaseMs, [this] { return "lease-" + std::to_string(++lease_counter); }};
  BookLeaser book{db, jobs, leases, clock,
                  [this] { return "lease-" + std::to_string(++lease_counter); }};
  TileMerger merger{db, clock};
  int lease_counter = 0;

  /// `path`: a file for what only a file shows (the WAL); the store is in memory by default.
  explicit StoreFixture(const std::string& path = ":memory:") : db(path) {
    migrate(db, clock.now_unix_ms());
  }

  /// A job of width x height pixels cut in tile x tile tiles and batches of `batch` spp.
  int64_t make_job(int width, int height, int tile, uint32_t spp, uint32_t batch, int priority = 0) {
    NewJob job;
    job.scene_file = "scene.json";
    job.bundle_bytes = "bundle of job " + std::to_string(++job_counter);
    job.bundle_sha256 = std::string(64 - std::to_string(job_counter).size(), 'a') +
                        std::to_string(job_counter);
    job.options.width = width;
    job.options.height = height;
    job.options.tile_size = tile;
    job.options.spp = spp;
    job.options.batch_spp = batch;
    job.priority = priority;
    return jobs.create(job, clock.now_unix_ms());
  }

  /// The job's tiles with their merged sums (checkpointed first: TileMerger::checkpoint_job).
  std::vector<TileRecord> tiles(int64_t job_id) {
    merger.checkpoint_job(job_id);
    return jobs.tiles(job_id);
  }

  int64_t make_worker(const std::string& name = "w") {
    return workers.register_worker({name, 4, "avx2", "0.1.0"}, clock.now_unix_ms());
  }

  /// A result for `rect` with `samples` samples per pixel whose sums depend on (batch, pixel):
  /// merging batches in different orders gives different bits for most values.
  static Accumulation synthetic(const TileRect& rect, uint32_t batch, uint32_t samples) {
    Accumulation acc(rect);
    for (size_t i = 0; i < acc.pixels(); ++i) {
      for (int c = 0; c < 3; ++c) {
        acc.rgb[i * 3 + c] = 0.1 * double(batch + 1) + 1e-3 * double(i) + 0.37 * c / double(batch + 3);
      }
      acc.lum2[i] = 1.0 / double(batch + 7 + i);
      acc.count[i] = samples;
    }
    return acc;
  }

  int job_counter = 0;
};

}  // namespace tessera::server::testing
