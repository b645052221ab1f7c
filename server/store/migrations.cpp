#include "store/migrations.h"

#include <algorithm>
#include <stdexcept>

namespace tessera::server {

const std::vector<Migration>& schema_migrations() {
  static const std::vector<Migration> kMigrations = {
      {1, "jobs, units, leases, bundles, tiles, pending results, workers", R"sql(
-- Scene bundles by SHA-256 of their canonical serialization (proto/wire/scene_bundle.h).
CREATE TABLE bundles (
  sha256          TEXT PRIMARY KEY,
  scene_file      TEXT NOT NULL,
  data            BLOB NOT NULL,             -- the canonical serialization
  size_bytes      INTEGER NOT NULL,
  created_unix_ms INTEGER NOT NULL
);

CREATE TABLE workers (
  id                 INTEGER PRIMARY KEY AUTOINCREMENT,
  name               TEXT NOT NULL,
  threads            INTEGER NOT NULL,
  isa                TEXT NOT NULL,
  version            TEXT NOT NULL,
  registered_unix_ms INTEGER NOT NULL,
  last_seen_unix_ms  INTEGER NOT NULL,
  units_done         INTEGER NOT NULL DEFAULT 0,   -- results accepted
  units_lost         INTEGER NOT NULL DEFAULT 0    -- leases expired or results dropped
);

CREATE TABLE jobs (
  id                INTEGER PRIMARY KEY AUTOINCREMENT,  -- never reused
  state             TEXT NOT NULL
                    CHECK (state IN ('queued', 'running', 'done', 'failed', 'cancelled')),
  priority          INTEGER NOT NULL,
  bundle_sha256     TEXT NOT NULL REFERENCES bundles (sha256),
  scene_file        TEXT NOT NULL,
  -- resolved job options (core/job/job_options.h)
  width             INTEGER NOT NULL,
  height            INTEGER NOT NULL,
  spp               INTEGER NOT NULL,
  max_depth         INTEGER NOT NULL,
  seed              INTEGER NOT NULL,   -- uint64 stored as its int64 bit pattern
  tile_size         INTEGER NOT NULL,
  batch_spp         INTEGER NOT NULL,
  isa               TEXT NOT NULL,
  tile_count        INTEGER NOT NULL,
  batch_count       INTEGER NOT NULL,
  units_total       INTEGER NOT NULL,   -- tile_count * batch_count
  -- counters, each updated in the transaction of the event it counts
  units_done        INTEGER NOT NULL DEFAULT 0,
  results_merged    INTEGER NOT NULL DEFAULT 0,
  results_dropped   INTEGER NOT NULL DEFAULT 0,
  leases_expired    INTEGER NOT NULL DEFAULT 0,
  units_released    INTEGER NOT NULL DEFAULT 0,
  samples_merged    INTEGER NOT NULL DEFAULT 0,   -- pixel samples: sum of pixels * batch spp
  nan_dropped       INTEGER NOT NULL DEFAULT 0,
  inf_dropped       INTEGER NOT NULL DEFAULT 0,
  submitted_unix_ms INTEGER NOT NULL,
  started_unix_ms   INTEGER NOT NULL DEFAULT 0,
  finished_unix_ms  INTEGER NOT NULL DEFAULT 0,
  error             TEXT NOT NULL DEFAULT '',
  output_exr        TEXT NOT NULL DEFAULT '',
  output_png        TEXT NOT NULL DEFAULT ''
);
CREATE INDEX jobs_schedule ON jobs (state, priority DESC, submitted_unix_ms, id);

-- The merged accumulation of each tile: batches [0, next_batch) summed in batch order.
CREATE TABLE tiles (
  job_id       INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  tile         INTEGER NOT NULL,          -- row-major index in the job's plan
  x0           INTEGER NOT NULL,
  y0           INTEGER NOT NULL,
  x1           INTEGER NOT NULL,
  y1           INTEGER NOT NULL,
  next_batch   INTEGER NOT NULL DEFAULT 0,
  accumulation BLOB,                      -- encode_accumulation; NULL until batch 0 is merged
  PRIMARY KEY (job_id, tile)
) WITHOUT ROWID;

-- Work units (job, tile, batch) and their lease. lease_id is set exactly when state = 'leased'.
CREATE TABLE units (
  id                    INTEGER PRIMARY KEY,
  job_id                INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  tile                  INTEGER NOT NULL,
  batch                 INTEGER NOT NULL,
  state                 TEXT NOT NULL
                        CHECK (state IN ('queued', 'leased', 'done', 'cancelled')),
  lease_id              TEXT,
  worker_id             INTEGER REFERENCES workers (id),
  lease_expires_unix_ms INTEGER,
  failures              INTEGER NOT NULL DEFAULT 0,
  UNIQUE (job_id, tile, batch),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE,
  CHECK ((state = 'leased') = (lease_id IS NOT NULL))
);
CREATE INDEX units_queue ON units (job_id, state, batch, tile);
CREATE UNIQUE INDEX units_lease ON units (lease_id) WHERE lease_id IS NOT NULL;
CREATE INDEX units_worker ON units (worker_id) WHERE state = 'leased';
CREATE INDEX units_expiry ON units (lease_expires_unix_ms) WHERE state = 'leased';

-- Accepted results that arrived before their tile's previous batches were merged.
CREATE TABLE pending_results (
  job_id           INTEGER NOT NULL,
  tile             INTEGER NOT NULL,
  batch            INTEGER NOT NULL,
  accumulation     BLOB NOT NULL,         -- encode_accumulation, as uploaded
  received_unix_ms INTEGER NOT NULL,
  PRIMARY KEY (job_id, tile, batch),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
) WITHOUT ROWID;

-- Failures a worker reported on a job (ReleaseUnit REASON_FAILED); 2 block it from the job.
CREATE TABLE job_worker_failures (
  job_id     INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  worker_id  INTEGER NOT NULL REFERENCES workers (id),
  failures   INTEGER NOT NULL,
  last_error TEXT NOT NULL,
  PRIMARY KEY (job_id, worker_id)
) WITHOUT ROWID;

-- Which renderers made a job's accepted results (provenance).
CREATE TABLE job_contributors (
  job_id  INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  isa     TEXT NOT NULL,
  version TEXT NOT NULL,
  PRIMARY KEY (job_id, isa, version)
) WITHOUT ROWID;
)sql"},
      {2, "stopping rules: job rule and outcome, per-tile error and verdict", R"sql(
-- The job's stopping rule (core/job/stopping_rule.h). jobs.spp is the plan's samples per pixel:
-- the spp rule's N, or the cap (max spp) of a time or noise job.
ALTER TABLE jobs ADD COLUMN stop_rule TEXT NOT NULL DEFAULT 'spp'
  CHECK (stop_rule IN ('spp', 'time', 'noise'));
ALTER TABLE jobs ADD COLUMN time_budget_ms INTEGER NOT NULL DEFAULT 0;  -- time rule
ALTER TABLE jobs ADD COLUMN noise_target REAL NOT NULL DEFAULT 0;       -- noise rule
-- When the scheduler found a time job over its budget (0 = not yet): no unit is leased after.
ALTER TABLE jobs ADD COLUMN budget_reached_unix_ms INTEGER NOT NULL DEFAULT 0;
-- Why the job stopped: '' while running (and for failed jobs), else a StopReason name.
ALTER TABLE jobs ADD COLUMN stop_reason TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN units_skipped INTEGER NOT NULL DEFAULT 0;   -- cancelled by the rule
ALTER TABLE jobs ADD COLUMN results_wasted INTEGER NOT NULL DEFAULT 0;  -- accepted, never merged

-- Each tile's estimated relative error after its last merge, and the rule's verdict:
-- '' open, else the StopReason that finished it (no batch is leased or merged after).
ALTER TABLE tiles ADD COLUMN error REAL NOT NULL DEFAULT 0;
ALTER TABLE tiles ADD COLUMN finished TEXT NOT NULL DEFAULT '';
)sql"},
      {3, "worker health (unit failures per worker, forgiveness, NaN/Inf), jobs per client", R"sql(
-- When the worker last failed the job: a block lapses --block-forgive-seconds after it.
ALTER TABLE job_worker_failures ADD COLUMN last_failure_unix_ms INTEGER NOT NULL DEFAULT 0;

-- Failures of one unit, per worker: K different workers failing a unit fail its job, with
-- every worker's reason.
CREATE TABLE unit_failures (
  unit_id              INTEGER NOT NULL REFERENCES units (id) ON DELETE CASCADE,
  worker_id            INTEGER NOT NULL REFERENCES workers (id),
  failures             INTEGER NOT NULL,
  last_error           TEXT NOT NULL,
  last_failure_unix_ms INTEGER NOT NULL,
  PRIMARY KEY (unit_id, worker_id)
) WITHOUT ROWID;

-- What each worker's accepted results held: pixel samples, and NaN/Inf samples it dropped.
ALTER TABLE workers ADD COLUMN samples_returned INTEGER NOT NULL DEFAULT 0;
ALTER TABLE workers ADD COLUMN nan_dropped INTEGER NOT NULL DEFAULT 0;
ALTER TABLE workers ADD COLUMN inf_dropped INTEGER NOT NULL DEFAULT 0;

-- Who submitted each job (the peer's address), for --max-queued-jobs.
CREATE TABLE job_clients (
  job_id INTEGER PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
  client TEXT NOT NULL
);
CREATE INDEX job_clients_client ON job_clients (client);
)sql"},
      {4, "batch schedules: progressive jobs, samples per pixel merged per tile", R"sql(
-- The job's batch schedule (core/job/batch_schedule.h): batch_spp is every batch of a 'fixed'
-- schedule, the cap of a 'progressive' one. Jobs stored before keep their fixed batches.
ALTER TABLE jobs ADD COLUMN batch_schedule TEXT NOT NULL DEFAULT 'fixed'
  CHECK (batch_schedule IN ('fixed', 'progressive'));

-- Samples per pixel merged into the tile: the end of its batch next_batch - 1 (0 before batch
-- 0), kept by the merger so that status reads no schedule.
ALTER TABLE tiles ADD COLUMN spp INTEGER NOT NULL DEFAULT 0;
UPDATE tiles SET spp = (SELECT MIN(tiles.next_batch * j.batch_spp, j.spp) FROM jobs j
                        WHERE j.id = tiles.job_id);
)sql"},
      // Deleted jobs give their pages back (PRAGMA incremental_vacuum after a delete): switching
      // an existing database to incremental auto-vacuum takes one VACUUM.
      {5, "incremental auto-vacuum", "PRAGMA auto_vacuum = INCREMENTAL; VACUUM;", true},
      {6, "lazy units: a tile's units come into being when leased", R"sql(
-- Each tile's units not yet created (store/tile_queue.h): batches [next_lease, lease_end) of
-- the tile have no row in `units` and count as queued; leasing batch next_lease inserts its
-- row (state 'leased') and moves next_lease on. lease_end is the job's batch_count, lowered to
-- next_lease when the tile needs no more batches (its stopping rule closed it, its job ended)
-- and to 1 when a time job ran out of budget. A submit so writes O(tiles) rows, whatever the spp.
CREATE TABLE tile_queue (
  job_id     INTEGER NOT NULL,
  tile       INTEGER NOT NULL,
  next_lease INTEGER NOT NULL,
  lease_end  INTEGER NOT NULL,
  PRIMARY KEY (job_id, tile),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
) WITHOUT ROWID;
-- The open tiles of a job in (batch, tile) order: the scheduler walks it and stops at the first.
CREATE INDEX tile_queue_open ON tile_queue (job_id, next_lease, tile)
  WHERE next_lease < lease_end;
-- Jobs stored before this migration have a row for every unit already: nothing is left to
-- create, their queued rows are leased as before.
INSERT INTO tile_queue (job_id, tile, next_lease, lease_end)
  SELECT t.job_id, t.tile, j.batch_count, j.batch_count FROM tiles t JOIN jobs j ON j.id = t.job_id;
)sql"},
      {7, "merged results kept as uploaded until their tile's checkpoint", R"sql(
-- A tile's merged sum is its checkpoint (tiles.accumulation: batches [0, c)) plus these rows,
-- batches [c, next_batch), as uploaded (server/merge_cache.h): accepting a result appends it
-- here instead of decoding, adding and re-encoding the stored tile. Every few batches, when
-- the tile finishes, and before anything reads tiles.accumulation, the merger writes the sum
-- as the new checkpoint and deletes the rows it covers.
CREATE TABLE merged_results (
  job_id       INTEGER NOT NULL,
  tile         INTEGER NOT NULL,
  batch        INTEGER NOT NULL,
  accumulation BLOB NOT NULL,             -- encode_accumulation, as uploaded
  PRIMARY KEY (job_id, tile, batch),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
) WITHOUT ROWID;
)sql"},
      {8, "one table of accepted results, written once", R"sql(
-- Every accepted result of a tile not yet in its checkpoint, as uploaded (store/results_table.h):
-- batches below the tile's next_batch are merged since its checkpoint, the others wait for an
-- earlier batch. A result is written once; merging it writes nothing here. Replaces
-- pending_results (waiting) and merged_results (merged), whose rows move over unchanged.
CREATE TABLE results (
  job_id       INTEGER NOT NULL,
  tile         INTEGER NOT NULL,
  batch        INTEGER NOT NULL,
  accumulation BLOB NOT NULL,             -- encode_accumulation, as uploaded
  PRIMARY KEY (job_id, tile, batch),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
) WITHOUT ROWID;
INSERT INTO results (job_id, tile, batch, accumulation)
  SELECT job_id, tile, batch, accumulation FROM merged_results;
INSERT INTO results (job_id, tile, batch, accumulation)
  SELECT job_id, tile, batch, accumulation FROM pending_results;
DROP TABLE merged_results;
DROP TABLE pending_results;
)sql"},
      {9, "results as a rowid table: the blobs out of the key's b-tree", R"sql(
-- Migration 8's `results` was WITHOUT ROWID: its b-tree is keyed by the whole row, so every
-- interior cell held a copy of a ~19 KB blob on overflow pages, and each insert or lookup
-- copied blobs together to compare keys (a third of the store's CPU per accepted result in a
-- profile: BENCHMARKS.md, "What a result and a job cost the server, counted"). Here the
-- rows live in a rowid table (blobs only in its leaves) and (job_id, tile, batch) is a unique
-- index of three integers. Every row moves over unchanged.
CREATE TABLE results_by_rowid (
  id           INTEGER PRIMARY KEY,
  job_id       INTEGER NOT NULL,
  tile         INTEGER NOT NULL,
  batch        INTEGER NOT NULL,
  accumulation BLOB NOT NULL,             -- encode_accumulation, as uploaded
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
);
INSERT INTO results_by_rowid (job_id, tile, batch, accumulation)
  SELECT job_id, tile, batch, accumulation FROM results ORDER BY job_id, tile, batch;
DROP TABLE results;
ALTER TABLE results_by_rowid RENAME TO results;
CREATE UNIQUE INDEX results_key ON results (job_id, tile, batch);
)sql"},
      {10, "tile checkpoints out of the tiles rows", R"sql(
-- A tile's checkpoint (~100-150 KB for a 64-px tile) was a column of its `tiles` row, ahead of
-- error, finished and spp (added later by ALTER TABLE): every statement that read those columns
-- walked the blob's chain of overflow pages to reach them, and every merge's UPDATE of the row
-- read the whole blob to rebuild the record. A job's status (six aggregates over its tiles,
-- read for every WatchJob message) cost 16 ms at 64 such tiles, and a merge 4x what it does
-- without the blob (BENCHMARKS.md, "What a result and a job cost the server, counted"). Here the
-- checkpoints live in a table of their own, a rowid table (the blobs only in its leaves) keyed
-- by (job_id, tile); every checkpoint moves over unchanged.
CREATE TABLE tile_checkpoints (
  job_id       INTEGER NOT NULL,
  tile         INTEGER NOT NULL,
  accumulation BLOB NOT NULL,             -- encode_accumulation of the tile's batches [0, c)
  PRIMARY KEY (job_id, tile),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
);
INSERT INTO tile_checkpoints (job_id, tile, accumulation)
  SELECT job_id, tile, accumulation FROM tiles WHERE accumulation IS NOT NULL
  ORDER BY job_id, tile;
ALTER TABLE tiles DROP COLUMN accumulation;
)sql"},
      {11, "jobs pinned to one renderer build", R"sql(
-- A job is leased only to workers of one renderer build (docs/design.md, "The determinism
-- contract"): pinned_build is the build of the worker its first lease went to (NULL: not
-- leased yet), any_build = 1 when it was submitted with --any-build (never pinned).
ALTER TABLE jobs ADD COLUMN any_build INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN pinned_build TEXT;
-- Jobs with accepted results keep what they had: one build -> pinned to it, several -> any.
UPDATE jobs
  SET pinned_build = (SELECT MIN(version) FROM job_contributors c WHERE c.job_id = jobs.id)
  WHERE (SELECT COUNT(DISTINCT version) FROM job_contributors c WHERE c.job_id = jobs.id) = 1;
UPDATE jobs SET any_build = 1
  WHERE (SELECT COUNT(DISTINCT version) FROM job_contributors c WHERE c.job_id = jobs.id) > 1;
)sql"},
      {12, "spot checks: a job's verify rate, quarantined workers", R"sql(
-- verify_rate: the fraction of a job's units rendered twice and compared (0: none; jobs from
-- before spot checks have none). A quarantined worker is known by its name, which outlives its
-- registrations (docs/reliability.md, "Spot checks"); no foreign key: a quarantine outlives its
-- job.
ALTER TABLE jobs ADD COLUMN verify_rate REAL NOT NULL DEFAULT 0;
CREATE TABLE worker_quarantines (
  worker_name TEXT PRIMARY KEY,
  job_id INTEGER NOT NULL,
  tile INTEGER NOT NULL,
  batch INTEGER NOT NULL,
  quarantined_unix_ms INTEGER NOT NULL,
  reason TEXT NOT NULL,
  finished_jobs TEXT NOT NULL  -- done jobs with its results then: "3,5,8"
);
)sql"},
      {13, "denoising: the jobs' flags and their units' guides", R"sql(
-- denoise = 1: the job's workers render the denoiser's guides over each pixel's first samples
-- and the server writes job-N.denoised.exr beside the raw files; guides = 1: the raw EXR holds
-- the guides as channels too.
ALTER TABLE jobs ADD COLUMN denoise INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN guides INTEGER NOT NULL DEFAULT 0;
-- The guides of each accepted unit that has them (encode_guide_tile, as uploaded), merged per
-- tile in batch order over the tile's merged batches when the image is written.
CREATE TABLE guide_results (
  job_id  INTEGER NOT NULL,
  tile    INTEGER NOT NULL,
  batch   INTEGER NOT NULL,
  guides  BLOB NOT NULL,
  PRIMARY KEY (job_id, tile, batch),
  FOREIGN KEY (job_id, tile) REFERENCES tiles (job_id, tile) ON DELETE CASCADE
);
)sql"},
  };
  return kMigrations;
}

int schema_version(Database& db) {
  db.exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations ("
      " version INTEGER PRIMARY KEY, name TEXT NOT NULL, applied_unix_ms INTEGER NOT NULL)");
  auto q = db.prepare("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
  q->step();
  return int(q->int64(0));
}

int migrate(Database& db, int64_t now_unix_ms, int up_to) {
  int version = schema_version(db);
  const auto& all = schema_migrations();
  const int newest = all.empty() ? 0 : all.back().version;
  if (version > newest) {
    throw std::runtime_error("database schema version " + std::to_string(version) +
                             " is newer than this tessera-server knows (" + std::to_string(newest) +
                             ")");
  }
  for (const Migration& m : all) {
    // Each migration applied once, by number (a gap in the numbers is allowed).
    bool applied = false;
    {
      auto q = db.prepare("SELECT 1 FROM schema_migrations WHERE version = ?");
      q->bind(1, m.version);
      applied = q->step();
    }
    if (applied) continue;
    if (m.version > up_to) break;
    if (m.outside_transaction) db.exec(m.sql);
    Transaction tx(db);
    if (!m.outside_transaction) db.exec(m.sql);
    db.prepare("INSERT INTO schema_migrations (version, name, applied_unix_ms) VALUES (?, ?, ?)")
        ->bind(1, m.version)
        .bind(2, m.name)
        .bind(3, now_unix_ms)
        .run();
    tx.commit();
    version = std::max(version, m.version);
  }
  return version;
}

int64_t migrations_applied(Database& db) {
  auto q = db.prepare("SELECT COUNT(*) FROM schema_migrations");
  q->step();
  return q->int64(0);
}

}  // namespace tessera::server
