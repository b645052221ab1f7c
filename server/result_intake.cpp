#include "result_intake.h"

#include <chrono>
#include <set>
#include <string>

#include "accum/accumulation_codec.h"
#include "accum/guide_tile_codec.h"
#include "call_trace.h"
#include "farm_error.h"

namespace tessera::server {
namespace {

/// Names result i in errors when the call carries several.
std::string which_result(const std::vector<UnitResult>& results, size_t i) {
  return results.size() > 1 ? "result " + std::to_string(i) + ": " : std::string();
}

/// A result's guides (a denoise job's) decode and cover its tile, checked outside the lock;
/// they are stored as uploaded.
void check_guides(const UnitResult& r, const TileRect& rect, const std::string& which) {
  if (r.guides.empty()) return;
  try {
    decode_guide_tile(r.guides, rect);
  } catch (const CodecError& e) {
    throw invalid_argument(which + "guides do not decode: " + e.what());
  }
}

}  // namespace

std::vector<AcceptOutcome> ResultIntake::upload_all(const std::vector<UnitResult>& results) {
  if (results.empty()) return {};
  const std::vector<int64_t> pixels = tile_pixels(results);
  const auto received = std::chrono::steady_clock::now();
  const int64_t decode_ns = call_trace::now_ns();
  std::vector<Accumulation> decoded(results.size());
  std::vector<TileMerger::Upload> uploads;
  for (size_t i = 0; i < results.size(); ++i) {
    try {
      decoded[i] = decode_accumulation(results[i].encoded, pixels[i]);
    } catch (const CodecError& e) {
      throw invalid_argument(which_result(results, i) + "result does not decode: " + e.what());
    }
    check_guides(results[i], decoded[i].rect, which_result(results, i));
    uploads.push_back({&results[i], &decoded[i]});
  }
  call_trace::record("decode", decode_ns, call_trace::now_ns(), int64_t(results.size()));
  // Results of jobs with spot checks, check leases' and quarantined workers' go through the
  // checks (spot_check_intake.cpp); the others as they always did.
  LeaseBook& book = store_.book();
  if (store_.checks().wants(results, [&book](int64_t job) { return book.verify_rate(job); })) {
    return upload_checked(results, decoded, received);
  }
  return commit_and_answer(uploads, received);
}

std::vector<AcceptOutcome> ResultIntake::commit_and_answer(
    const std::vector<TileMerger::Upload>& uploads,
    std::chrono::steady_clock::time_point received) {
  // The worker was checked (and its last call recorded) by tile_pixels; workers are never
  // removed.
  UploadCall call;
  call.uploads = &uploads;
  const int64_t commit_ns = call_trace::now_ns();
  commits_.run(call);
  call_trace::record("commit_wait", commit_ns, call_trace::now_ns(), int64_t(uploads.size()));
  if (call.error) std::rethrow_exception(call.error);
  answered(uploads, call.outcomes,
           std::chrono::duration<double>(std::chrono::steady_clock::now() - received).count());
  return call.outcomes;
}

std::vector<int64_t> ResultIntake::tile_pixels(const std::vector<UnitResult>& results) {
  // The unit's tile bounds what decoding may allocate: the codec sizes its buffers from the
  // result's header, and a few kilobytes of zstd can declare gigabytes (docs/reliability.md,
  // "A hostile result"). So the worker and the tiles are looked up first, and a header declaring
  // more pixels than the tile is refused before anything is decompressed.
  // Both from memory, as a lease's check of the worker: no store lock unless the worker or a
  // tile is new to this server.
  const int64_t asked_ns = call_trace::now_ns();
  presence_.touch_in_memory(results.front().worker_id, presence_.begin_call());
  const std::vector<std::optional<TileRect>> rects = tile_rects(results);
  call_trace::record("upload_lock", asked_ns, call_trace::now_ns());
  std::vector<int64_t> pixels;
  for (size_t i = 0; i < results.size(); ++i) {
    const UnitResult& r = results[i];
    if (!rects[i]) {
      throw FarmError(ErrorCode::not_found,
                      which_result(results, i) + "no unit job " + std::to_string(r.job_id) +
                          " tile " + std::to_string(r.tile) + " batch " + std::to_string(r.batch));
    }
    pixels.push_back(rects[i]->pixel_count());
  }
  return pixels;
}

std::vector<std::optional<TileRect>> ResultIntake::tile_rects(
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
  FarmStore::Lock lock(store_);
  for (size_t i = 0; i < results.size(); ++i) {
    if (rects[i]) continue;
    rects[i] = store_.jobs().tile_rect(results[i].job_id, results[i].tile);
    if (!rects[i]) continue;
    std::lock_guard kept(tile_rects_mu_);
    if (tile_rects_.size() >= kTileRectsKept) tile_rects_.clear();
    tile_rects_.emplace(std::pair(results[i].job_id, results[i].tile), *rects[i]);
  }
  return rects;
}

void ResultIntake::forget_job(int64_t job_id) {
  merger_.forget_job(job_id);
  std::lock_guard rects(tile_rects_mu_);
  tile_rects_.erase(tile_rects_.lower_bound({job_id, 0}),
                    tile_rects_.lower_bound({job_id + 1, 0}));
}

void ResultIntake::answered(const std::vector<TileMerger::Upload>& uploads,
                            const std::vector<AcceptOutcome>& outcomes, double seconds) {
  std::set<int64_t> complete;
  bool frees_work = false;
  for (size_t i = 0; i < uploads.size(); ++i) {
    const UnitResult& r = *uploads[i].result;
    if (observer_) {
      observer_->record_result(r.worker_id, r.job_id, outcomes[i].accepted, outcomes[i].samples,
                               seconds);
    }
    // The worker's rate, which bounds its next leases (leasing.h, lease_sample_budget).
    if (outcomes[i].accepted) {
      presence_.rates().record(r.worker_id, outcomes[i].samples, r.render_ms);
    }
    if (outcomes[i].job_complete) complete.insert(r.job_id);
    frees_work = frees_work || outcomes[i].frees_work;
  }
  // Progress for watchers; idle workers' long polls only when a merge may have let a unit be
  // leased (a noise tile's lookahead moved): at a job's end, waking every idle worker's poll on
  // every upload would wake them for nothing.
  events_.notify(frees_work);
  for (int64_t id : complete) finish_job_(id);
}

void ResultIntake::commit_upload(UploadCall& call) {
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

void ResultIntake::commit_uploads(const std::vector<UploadCall*>& calls) {
  // Leases first: this group's transaction starts once no lease or heartbeat waits for the lock,
  // and it ends early, between two calls, when one comes to wait meanwhile: the calls left commit
  // in the next transaction, after the lease. A lease then waits for at most one call's results
  // (at most 64), not for the whole group (up to kResultsPerCommit; BENCHMARKS.md, "Lease
  // latency and capacity").
  if (before_commit_) {
    size_t results = 0;
    for (const UploadCall* c : calls) results += c->uploads->size();
    before_commit_(results);
  }
  const int64_t asked_ns = call_trace::now_ns();
  PriorityMutex::Deferring lock(store_.mutex());
  const int64_t got_ns = call_trace::now_ns();
  struct Traced {
    int64_t asked, got;
    size_t calls;
    ~Traced() {
      call_trace::record("group_lock", asked, got, int64_t(calls));
      call_trace::record("group", got, call_trace::now_ns(), int64_t(calls));
    }
  } traced{asked_ns, got_ns, calls.size()};
  size_t next = 0;  // the first call not committed yet
  while (next < calls.size()) {
    if (next > 0) lock.yield();  // the callers waiting Urgent go first
    // The leases answered so far reach the store before their results (flush_leases).
    try {
      store_.flush_leases();
    } catch (...) {
      for (; next < calls.size(); ++next) calls[next]->error = std::current_exception();
      break;
    }
    if (next + 1 == calls.size()) {
      commit_upload(*calls[next++]);
      break;
    }
    next = commit_together(calls, next);
  }
  follow_merges(calls);
}

size_t ResultIntake::commit_together(const std::vector<UploadCall*>& calls, size_t next) {
  std::vector<TileMerger::Upload> all;
  std::vector<size_t> ends;
  for (size_t c = next; c < calls.size(); ++c) {
    all.insert(all.end(), calls[c]->uploads->begin(), calls[c]->uploads->end());
    ends.push_back(all.size());
  }
  const auto lease_waits = [this] { return store_.mutex().urgent_waiting() > 0; };
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
  return next;
}

void ResultIntake::follow_merges(const std::vector<UploadCall*>& calls) {
  // The lease book follows: accepted (or dropped) leases end; a merge moves its tile's prefix
  // (a noise tile's lookahead) or closes the tile. Still under the lock, so no store operation
  // sees the book behind the store.
  LeaseBook& book = store_.book();
  for (const UploadCall* c : calls) {
    if (c->error) continue;
    for (size_t i = 0; i < c->uploads->size(); ++i) {
      const UnitResult& r = *(*c->uploads)[i].result;
      const AcceptOutcome& o = c->outcomes[i];
      if (o.accepted) book.ended(r.lease_id);
      if (o.tile_next_batch) book.tile_merged(r.job_id, r.tile, *o.tile_next_batch, o.tile_closed);
    }
  }
  for (const UploadCall* c : calls) {
    if (c->error) continue;
    for (size_t i = 0; i < c->uploads->size(); ++i) {
      // Only NaN/Inf samples can move a worker over the report threshold.
      const TileMerger::Upload& u = (*c->uploads)[i];
      if (c->outcomes[i].accepted && u.decoded->nan_dropped + u.decoded->inf_dropped > 0) {
        presence_.report_health(u.result->worker_id);
      }
    }
  }
}

}  // namespace tessera::server
