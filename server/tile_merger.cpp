#include "tile_merger.h"

#include <bit>
#include <optional>
#include <vector>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "farm_error.h"
#include "job/job_plan.h"
#include "job/tile_verdict.h"
#include "job/stopping_rule.h"
#include "job_state.h"
#include "job_store.h"
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

/// Counters of the merged results, added to the job's with its units_done.
struct MergeTally : MergedCounts {
  void add(const Accumulation& acc, uint32_t batch_samples) {
    ++results;
    pixel_samples += uint64_t(acc.pixels()) * batch_samples;
    nan += acc.nan_dropped;
    inf += acc.inf_dropped;
  }
};

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
    for (const auto& [worker_id, d] : staged.delivered) {
      WorkersTable(db_).count_delivered(worker_id, d.units, d.samples, d.nan, d.inf);
    }
    for (const auto& [job_id, a] : staged.accepted) {
      JobsTable(db_).count_accepted(job_id, a.units, a.merged);
    }
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
  contributors_.insert(staged.contributors.begin(), staged.contributors.end());
  return outcomes;
}

AcceptOutcome TileMerger::accept_in_transaction(const UnitResult& r, Accumulation& decoded,
                                                Staged& staged) {
  AcceptOutcome outcome;
  std::optional<MergeCache::Tile> cached;  // the tile's sum while this call merges into it
  const std::optional<UnitForResult> c = UnitsTable(db_).for_result(r.job_id, r.tile, r.batch);
  if (!c) {
    throw FarmError(ErrorCode::not_found, "no unit job " + std::to_string(r.job_id) + " tile " +
                                              std::to_string(r.tile) + " batch " +
                                              std::to_string(r.batch));
  }
  validate(r, *c, decoded);

  // The compare-and-set: only the current lease of this unit, held by this worker, completes it.
  if (UnitsTable(db_).accept(c->unit_id, r.worker_id, r.lease_id) != 1) {
    JobsTable(db_).count_dropped(r.job_id);
    // A unit cancelled under the worker (its job was cancelled or failed, or the stopping rule
    // no longer needs it) is not the worker's failure: only a lost lease counts against it.
    if (!c->cancelled) {
      WorkersTable(db_).count_lost(r.worker_id);
    }
    outcome.reason =
        "lease " + r.lease_id + " is not the current lease of the unit (expired and re-leased, "
        "already delivered, or the job ended)";
    return outcome;
  }
  outcome.accepted = true;
  MergeTally tally;  // what this call merged, added to the job's counters with units_done
  {
    for (uint32_t n : decoded.count) outcome.samples += n;
    Staged::Delivered& d = staged.delivered[r.worker_id];
    ++d.units;
    d.samples += outcome.samples + decoded.nan_dropped + decoded.inf_dropped;
    d.nan += decoded.nan_dropped;
    d.inf += decoded.inf_dropped;
  }
  const Contributor contributor{r.job_id, r.worker_id, r.isa};
  if (!contributors_.contains(contributor) && !staged.contributors.contains(contributor)) {
    JobContributorsTable(db_).add(r.job_id, r.isa, r.worker_id);
  }

  ResultsTable results(db_);
  if (r.batch != c->next_batch) {
    // Earlier batches of this tile are missing: keep the result, durably, until they come. Its
    // row stays where it is when it merges (store/results_table.h).
    results.append(r.job_id, r.tile, r.batch, r.encoded);
    staged.waiting.insert_or_assign({r.job_id, r.tile, r.batch}, &decoded);
  } else {
    // Merge this batch, then every waiting successor, strictly in batch order, judging the
    // tile by the job's stopping rule after each (determinism contract rule 4): once it is
    // finished nothing more merges into it, whatever else has arrived. The sum comes from the
    // merge cache, or is rebuilt from the checkpoint and the merged rows of `results`.
    cached = load_sum(r.job_id, r.tile, c->rect, c->next_batch, &staged);
    Accumulation& tile = cached->sum;
    uint32_t next = c->next_batch;
    const Accumulation* batch = &decoded;
    Accumulation successor;
    TileVerdict verdict;
    bool error_read = false;  // the last verdict computed the tile's error
    for (;;) {
      tile.merge(*batch);
      tally.add(*batch, c->plan.batch_end(next) - c->plan.batch_begin(next));
      ++next;
      // The error only where the rule reads it (a noise tile from 16 spp on); where it is only
      // stored, it is computed once below.
      const uint32_t spp = c->plan.batch_end(next - 1);
      error_read = verdict_reads_error(c->rule, spp);
      verdict = judge_tile_given_error(c->rule, c->noise_target,
                                       error_read ? estimate_relative_error(tile) : 0.0, next,
                                       c->plan.batch_count(), spp);
      if (verdict.finished) break;
      // The waiting successor: decoded in memory when this transaction or an earlier one kept
      // it (WaitingResults), else its row read back and decoded.
      if (const auto it = staged.waiting.find({r.job_id, r.tile, next});
          it != staged.waiting.end()) {
        batch = it->second;  // this transaction's upload: merged in place, not copied
        staged.waiting.erase(it);
        ++waiting_hits_;
      } else if (std::optional<Accumulation> kept = waiting_.take(r.job_id, r.tile, next)) {
        successor = std::move(*kept);
        batch = &successor;
        staged.taken.emplace(r.job_id, r.tile);
        ++waiting_hits_;
      } else if (!may_wait_in_store(r.job_id, r.tile)) {
        break;  // not arrived: every waiting result of this tile is in memory
      } else {
        std::optional<std::string> row = results.find(r.job_id, r.tile, next);
        if (!row) break;
        successor = decode_accumulation(*row);
        batch = &successor;
      }
      ++waiting_merged_;
    }
    cached->next_batch = next;
    const bool checkpoint = verdict.finished || next - cached->checkpointed >= checkpoint_every_;
    // The stored error (status, the output's provenance): after every merge where the rule reads
    // it, else at each checkpoint (so exact when the tile ends) and when the tile's spp reaches a
    // power of two; in between the tile keeps the one stored last. Computing it for every merged
    // batch cost 2.4-4.2 % of the server's CPU (BENCHMARKS.md, "What a result and a job cost the
    // server, counted").
    std::optional<double> error;
    if (error_read) {
      error = verdict.relative_error;
    } else if (checkpoint || std::has_single_bit(c->plan.schedule().spp_after(next))) {
      error = estimate_relative_error(tile);
    }
    if (checkpoint) {
      // Checkpoint: the sum becomes the stored tile; the rows it covers (the successors merged
      // here among them) go, and this result is never written.
      write_checkpoint(r.job_id, r.tile, tile, next);
      cached->checkpointed = next;
    } else {
      // The uploaded bytes as they came; merged successors keep their rows, now below the
      // tile's next_batch.
      results.append(r.job_id, r.tile, r.batch, r.encoded);
    }
    if (verdict.finished) close_tile(r.job_id, r.tile, next);
    const TileProgress progress{next, error, verdict.reason, c->plan.schedule().spp_after(next)};
    if (!TilesTable(db_).advance(r.job_id, r.tile, c->next_batch, progress)) {
      throw FarmError(ErrorCode::internal, "tile " + std::to_string(r.tile) + " of job " +
                                               std::to_string(r.job_id) +
                                               " changed during its merge");
    }
    outcome.merged = tally.results;
    outcome.frees_work = c->rule == StopRule::noise && tally.results > 0;
    outcome.tile_next_batch = next;
    outcome.tile_closed = verdict.finished;
  }
  Staged::Accepted& a = staged.accepted[r.job_id];
  ++a.units;
  a.merged.results += tally.results;
  a.merged.pixel_samples += tally.pixel_samples;
  a.merged.nan += tally.nan;
  a.merged.inf += tally.inf;
  if (cached) staged.tiles.insert_or_assign({r.job_id, r.tile}, std::move(*cached));
  staged.contributors.insert(contributor);
  return outcome;
}

void TileMerger::write_checkpoint(int64_t job_id, uint32_t tile, const Accumulation& sum,
                                  uint32_t next_batch) {
  TilesTable(db_).write_checkpoint(job_id, tile, checkpoint_encoder_.encode(sum, kCheckpointEffort));
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
