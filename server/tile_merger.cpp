#include "tile_merger.h"

#include <bit>
#include <optional>
#include <vector>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "accum/guide_tile.h"
#include "farm_error.h"
#include "job/job_plan.h"
#include "job/tile_verdict.h"
#include "job/stopping_rule.h"
#include "store/job_state.h"
#include "job_store.h"
#include "store/guide_results_table.h"
#include "store/job_contributors_table.h"
#include "store/jobs_table.h"
#include "store/results_table.h"
#include "store/tile_queue.h"
#include "store/tiles_table.h"
#include "store/units_table.h"
#include "store/workers_table.h"

namespace tessera::server {
namespace {

void validate(const UnitResult& r, const UnitForResult& c, const Accumulation& acc) {
  const std::string unit = "job " + std::to_string(r.job_id) + " tile " + std::to_string(r.tile) +
                           " batch " + std::to_string(r.batch);
  if (!(acc.rect == c.rect) || acc.pixels() != size_t(c.rect.pixel_count()) ||
      acc.rgb.size() != acc.pixels() * 3 || acc.lum2.size() != acc.pixels()) {
    throw FarmError(ErrorCode::invalid_argument,
                    "result for " + unit + " does not cover the unit's tile");
  }
  const uint32_t samples = c.plan.batch_end(r.batch) - c.plan.batch_begin(r.batch);
  for (uint32_t n : acc.count) {
    if (n > samples) {
      throw FarmError(ErrorCode::invalid_argument,
                      "result for " + unit + " has a pixel with " + std::to_string(n) +
                          " samples; the batch has " + std::to_string(samples));
    }
  }
}

/// Counts a merged batch of `batch_samples` samples per pixel.
void count_merged(MergedCounts& merged, const Accumulation& batch, uint32_t batch_samples) {
  ++merged.results;
  merged.pixel_samples += uint64_t(batch.pixels()) * batch_samples;
  merged.nan += batch.nan_dropped;
  merged.inf += batch.inf_dropped;
}

}  // namespace

void TileMerger::close_tile(int64_t job_id, uint32_t tile, uint32_t next_batch) {
  // The tile's later units are not needed: queued or leased, they are skipped (a leased one's
  // result will be stale and dropped); results already accepted for later batches are wasted.
  int64_t skipped = UnitsTable(db_).skip_tile(job_id, tile);
  skipped += TileQueue(db_).close_tile(job_id, tile);  // and those without a row yet
  const int64_t wasted = ResultsTable(db_).drop_waiting_of_tile(job_id, tile, next_batch);
  JobsTable(db_).count_skipped(job_id, skipped, wasted);
}

AcceptOutcome TileMerger::accept(const UnitResult& r, const Accumulation& decoded) {
  Accumulation copy = decoded;  // accept_all may keep it (a waiting result)
  return accept_all({Upload{&r, &copy}}).front();
}

bool TileMerger::may_wait_in_store(int64_t job_id, uint32_t tile) {
  if (jobs_seen_.insert(job_id).second) {
    for (const uint32_t t : ResultsTable(db_).tiles_with_rows(job_id)) {
      store_only_.emplace(job_id, t);
    }
  }
  return store_only_.contains({job_id, tile});
}

std::vector<AcceptOutcome> TileMerger::accept_all(const std::vector<Upload>& uploads) {
  return accept_calls(uploads, {uploads.size()}, {});
}

std::vector<AcceptOutcome> TileMerger::accept_calls(const std::vector<Upload>& uploads,
                                                    const std::vector<size_t>& ends,
                                                    const std::function<bool()>& stop) {
  Staged staged;
  std::vector<AcceptOutcome> outcomes;
  outcomes.reserve(uploads.size());
  try {
    Transaction tx(db_);
    std::map<int64_t, bool> complete;  // per job of the calls: no unit queued or leased
    size_t call = 0;  // the call of the next upload: [ends[call - 1], ends[call])
    for (const Upload& u : uploads) {
      outcomes.push_back(accept_in_transaction(*u.result, *u.decoded, staged));
      complete.try_emplace(u.result->job_id, false);
      if (call < ends.size() && outcomes.size() == ends[call]) {
        ++call;
        if (call < ends.size() && stop && stop()) break;  // the others in a later transaction
      }
    }
    staged.ledger.write(db_, contributors_);  // the counters, in this transaction
    // Asked once per job after the call's last result, not after each.
    for (auto& [job_id, done] : complete) done = !units_left(db_, job_id);
    for (size_t i = 0; i < outcomes.size(); ++i) {
      outcomes[i].job_complete = complete.at(uploads[i].result->job_id);
    }
    tx.commit();
  } catch (...) {
    // Rolled back: the waiting results this transaction took from memory are waiting again,
    // in the store only.
    store_only_.insert(staged.taken.begin(), staged.taken.end());
    throw;
  }
  // Only committed sums go to the cache (an exception above leaves them out: they are rebuilt
  // from the store next time).
  for (auto& [key, tile] : staged.tiles) cache_.put(key.first, key.second, std::move(tile));
  for (auto& [key, result] : staged.waiting) {
    for (const auto& tile : waiting_.put(std::get<0>(key), std::get<1>(key), std::get<2>(key),
                                         std::move(*result))) {
      store_only_.insert(tile);  // evicted: its row is in the store only
    }
  }
  contributors_.insert(staged.ledger.contributors().begin(), staged.ledger.contributors().end());
  return outcomes;
}

AcceptOutcome TileMerger::accept_in_transaction(const UnitResult& r, Accumulation& decoded,
                                                Staged& staged) {
  const UnitForResult unit = unit_for(r, decoded);
  // The compare-and-set: only the current lease of this unit, held by this worker, completes it.
  if (UnitsTable(db_).accept(unit.unit_id, r.worker_id, r.lease_id) != 1) {
    return drop_stale(r, unit);
  }
  AcceptOutcome outcome;
  outcome.accepted = true;
  for (uint32_t n : decoded.count) outcome.samples += n;
  staged.ledger.delivered(r.worker_id, outcome.samples, decoded.nan_dropped, decoded.inf_dropped);
  staged.ledger.contributed({r.job_id, r.worker_id, r.isa});
  // A denoise job's guides (decoded by the intake) wait for the image in a table of their own.
  if (!r.guides.empty()) store_guides(r, unit);
  MergedCounts merged;
  if (r.batch == unit.next_batch) {
    merged = merge(r, unit, decoded, staged, outcome);
  } else {
    // Earlier batches of this tile are missing: keep the result, durably, until they come. Its
    // row stays where it is when it merges (store/results_table.h).
    ResultsTable(db_).append(r.job_id, r.tile, r.batch, r.encoded);
    staged.waiting.insert_or_assign({r.job_id, r.tile, r.batch}, &decoded);
  }
  staged.ledger.accepted(r.job_id, merged);
  return outcome;
}

UnitForResult TileMerger::unit_for(const UnitResult& r, const Accumulation& decoded) {
  std::optional<UnitForResult> unit = UnitsTable(db_).for_result(r.job_id, r.tile, r.batch);
  if (!unit) {
    throw FarmError(ErrorCode::not_found, "no unit job " + std::to_string(r.job_id) + " tile " +
                                              std::to_string(r.tile) + " batch " +
                                              std::to_string(r.batch));
  }
  validate(r, *unit, decoded);
  return std::move(*unit);
}

void TileMerger::store_guides(const UnitResult& r, const UnitForResult& unit) {
  // Only what the unit's lease asked for (WorkUnit.guide_sample_end): a denoise job's unit over
  // the guides' first samples. Anything else is the worker's mistake, refused as a bad result.
  if (unit.plan.batch_begin(r.batch) >= kGuideSamples ||
      !GuideResultsTable(db_).put(r.job_id, r.tile, r.batch, r.guides)) {
    throw FarmError(ErrorCode::invalid_argument,
                    "result for job " + std::to_string(r.job_id) + " tile " +
                        std::to_string(r.tile) + " batch " + std::to_string(r.batch) +
                        " carries guides its unit did not ask for");
  }
}

AcceptOutcome TileMerger::drop_stale(const UnitResult& r, const UnitForResult& unit) {
  JobsTable(db_).count_dropped(r.job_id);
  // A unit cancelled under the worker (its job was cancelled or failed, or the stopping rule no
  // longer needs it) is not the worker's failure: only a lost lease counts against it.
  if (!unit.cancelled) WorkersTable(db_).count_lost(r.worker_id);
  AcceptOutcome outcome;
  outcome.reason =
      "lease " + r.lease_id + " is not the current lease of the unit (expired and re-leased, "
      "already delivered, or the job ended)";
  return outcome;
}

MergedCounts TileMerger::merge(const UnitResult& r, const UnitForResult& unit,
                               Accumulation& decoded, Staged& staged, AcceptOutcome& outcome) {
  // The sum comes from the merge cache, or is rebuilt from the checkpoint and the merged rows of
  // `results`.
  MergeCache::Tile cached = load_sum(r.job_id, r.tile, unit.rect, unit.next_batch, &staged);
  const MergeRun run = merge_in_order(r, unit, cached.sum, decoded, staged);
  store_merge(r, unit, cached, run);
  outcome.merged = run.merged.results;
  outcome.frees_work = unit.rule == StopRule::noise && run.merged.results > 0;
  outcome.tile_next_batch = run.next_batch;
  outcome.tile_closed = run.verdict.finished;
  staged.tiles.insert_or_assign({r.job_id, r.tile}, std::move(cached));
  return run.merged;
}

TileMerger::MergeRun TileMerger::merge_in_order(const UnitResult& r, const UnitForResult& unit,
                                                Accumulation& sum, const Accumulation& first,
                                                Staged& staged) {
  // Determinism contract rule 4: once the rule finishes the tile nothing more merges into it,
  // whatever else has arrived.
  MergeRun run;
  run.next_batch = unit.next_batch;
  const JobPlan& plan = unit.plan;
  const Accumulation* batch = &first;
  Accumulation successor;
  for (;;) {
    sum.merge(*batch);
    count_merged(run.merged, *batch,
                 plan.batch_end(run.next_batch) - plan.batch_begin(run.next_batch));
    ++run.next_batch;
    // The error only where the rule reads it (a noise tile from 16 spp on); where it is only
    // stored, store_merge computes it once.
    const uint32_t spp = plan.batch_end(run.next_batch - 1);
    run.error_read = verdict_reads_error(unit.rule, spp);
    run.verdict = judge_tile_given_error(unit.rule, unit.noise_target,
                                         run.error_read ? estimate_relative_error(sum) : 0.0,
                                         run.next_batch, plan.batch_count(), spp);
    if (run.verdict.finished) break;
    batch = waiting_successor(r, run.next_batch, staged, successor);
    if (!batch) break;
    ++waiting_merged_;
  }
  return run;
}

const Accumulation* TileMerger::waiting_successor(const UnitResult& r, uint32_t batch,
                                                  Staged& staged, Accumulation& successor) {
  if (const auto it = staged.waiting.find({r.job_id, r.tile, batch}); it != staged.waiting.end()) {
    const Accumulation* kept = it->second;  // this transaction's upload: merged in place
    staged.waiting.erase(it);
    ++waiting_hits_;
    return kept;
  }
  if (std::optional<Accumulation> kept = waiting_.take(r.job_id, r.tile, batch)) {
    successor = std::move(*kept);
    staged.taken.emplace(r.job_id, r.tile);
    ++waiting_hits_;
    return &successor;
  }
  if (!may_wait_in_store(r.job_id, r.tile)) return nullptr;  // every waiting one is in memory
  const std::optional<std::string> row = ResultsTable(db_).find(r.job_id, r.tile, batch);
  if (!row) return nullptr;
  successor = decode_accumulation(*row);
  return &successor;
}

void TileMerger::store_merge(const UnitResult& r, const UnitForResult& unit,
                             MergeCache::Tile& cached, const MergeRun& run) {
  const uint32_t next = run.next_batch;
  cached.next_batch = next;
  const bool checkpoint = run.verdict.finished || next - cached.checkpointed >= checkpoint_every_;
  // The stored error (status, the output's provenance): after every merge where the rule reads
  // it, else at each checkpoint (so exact when the tile ends) and when the tile's spp reaches a
  // power of two; in between the tile keeps the one stored last. Computing it for every merged
  // batch cost 2.4-4.2 % of the server's CPU (BENCHMARKS.md, "What a result and a job cost the
  // server, counted").
  std::optional<double> error;
  if (run.error_read) {
    error = run.verdict.relative_error;
  } else if (checkpoint || std::has_single_bit(unit.plan.schedule().spp_after(next))) {
    error = estimate_relative_error(cached.sum);
  }
  if (checkpoint) {
    // The sum becomes the stored tile; the rows it covers (the successors merged here among
    // them) go, and this result is never written.
    write_checkpoint(r.job_id, r.tile, cached.sum, next);
    cached.checkpointed = next;
  } else {
    // The uploaded bytes as they came; merged successors keep their rows, now below the tile's
    // next_batch.
    ResultsTable(db_).append(r.job_id, r.tile, r.batch, r.encoded);
  }
  if (run.verdict.finished) close_tile(r.job_id, r.tile, next);
  const TileProgress progress{next, error, run.verdict.reason,
                              unit.plan.schedule().spp_after(next)};
  if (!TilesTable(db_).advance(r.job_id, r.tile, unit.next_batch, progress)) {
    throw FarmError(ErrorCode::internal, "tile " + std::to_string(r.tile) + " of job " +
                                             std::to_string(r.job_id) +
                                             " changed during its merge");
  }
}

void TileMerger::write_checkpoint(int64_t job_id, uint32_t tile, const Accumulation& sum,
                                  uint32_t next_batch) {
  TilesTable(db_).write_checkpoint(job_id, tile,
                                   checkpoint_encoder_.encode(sum, kCheckpointEffort));
  ResultsTable(db_).drop_merged(job_id, tile, next_batch);
}

MergeCache::Tile TileMerger::load_sum(int64_t job_id, uint32_t tile, const TileRect& rect,
                                      uint32_t next_batch, Staged* staged) {
  if (staged) {
    const auto it = staged->tiles.find({job_id, tile});
    if (it != staged->tiles.end()) {
      MergeCache::Tile t = std::move(it->second);
      staged->tiles.erase(it);
      if (t.next_batch == next_batch) return t;
    }
  }
  if (std::optional<MergeCache::Tile> hit = cache_.take(job_id, tile, next_batch)) {
    return std::move(*hit);
  }
  MergeCache::Tile t{Accumulation(rect), next_batch};
  if (const std::optional<std::string> stored = TilesTable(db_).checkpoint(job_id, tile)) {
    t.sum = decode_accumulation(*stored);
  }
  // The checkpoint holds batches [0, first); the results table holds [first, next_batch), in
  // order (and maybe results waiting beyond next_batch, not part of the sum).
  ResultsTable results(db_);
  uint32_t expected = results.first_merged(job_id, tile, next_batch);
  t.checkpointed = expected;
  results.for_each_merged(job_id, tile, next_batch, [&](uint32_t batch, const std::string& bytes) {
    if (batch != expected) {
      throw FarmError(ErrorCode::internal,
                      "tile " + std::to_string(tile) + " of job " + std::to_string(job_id) +
                          ": merged results do not continue its checkpoint in batch order");
    }
    t.sum.merge(decode_accumulation(bytes));
    ++expected;
  });
  if (expected != next_batch) {
    throw FarmError(ErrorCode::internal, "tile " + std::to_string(tile) + " of job " +
                                             std::to_string(job_id) + ": merged results end at "
                                             "batch " + std::to_string(expected) + ", not " +
                                             std::to_string(next_batch));
  }
  return t;
}

void TileMerger::checkpoint_job(int64_t job_id) {
  std::vector<std::pair<uint32_t, MergeCache::Tile>> written;
  Transaction tx(db_);
  for (const uint32_t tile : ResultsTable(db_).tiles_with_merged(job_id)) {
    const std::optional<TilePosition> at = TilesTable(db_).position(job_id, tile);
    if (!at) continue;
    MergeCache::Tile t = load_sum(job_id, tile, at->rect, at->next_batch);
    write_checkpoint(job_id, tile, t.sum, at->next_batch);
    t.checkpointed = t.next_batch;
    written.emplace_back(tile, std::move(t));
  }
  tx.commit();
  for (auto& [tile, t] : written) cache_.put(job_id, tile, std::move(t));
}

}  // namespace tessera::server
