// A migrated :memory: store with the farm's components over a fake clock, and helpers that make
// jobs, workers and results without scenes or a renderer.
#pragma once

#include <fstream>
#include <iterator>
#include <string>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "fake_clock.h"
#include "job_store.h"
#include "lease_table.h"
#include "scheduler.h"
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

struct StoreFixture {
  static constexpr int64_t kLeaseMs = 10'000;

  FakeClock clock;
  Database db{":memory:"};
  JobStore jobs{db};
  WorkerRegistry workers{db};
  LeaseTable leases{db, jobs, clock, kLeaseMs, [this] { return "lease-" + std::to_string(++lease_counter); }};
  Scheduler scheduler{db, leases, clock};
  TileMerger merger{db, clock};
  int lease_counter = 0;

  StoreFixture() { migrate(db, clock.now_unix_ms()); }

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
