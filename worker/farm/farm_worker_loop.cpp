#include "farm_worker_loop.h"

#include <tbb/info.h>

#include <algorithm>
#include <exception>
#include <new>
#include <utility>

#include "accum/accumulation_codec.h"
#include "accum/guide_tile_codec.h"
#include "call_errors.h"
#include "fault_seam.h"
#include "render/renderer_build.h"
#include "scene/scene_error.h"
#include "wire/job_options_wire.h"
#include "wire/rpc_channel.h"
#include "worker_identity.h"
#include "worker_log.h"

namespace tessera::farm {

using std::chrono::milliseconds;

namespace {

/// How long a LeaseUnit call may wait on the server for work (a signal cancels it at once).
constexpr uint32_t kLeaseWaitMs = 5000;
/// How long to keep retrying an upload while the server is unreachable before dropping the
/// result (its lease is revoked by then: a restarted server re-queues every lease).
constexpr milliseconds kUploadGiveUp{120'000};
/// Units per LeaseUnit call (docs/farm.md, "Batched calls"): small units are leased and their
/// results uploaded several at a time, about this many samples per render thread per call (a
/// few tens of milliseconds of work: leases stay short), at most kMaxUnitsPerCall.
constexpr uint64_t kSamplesPerThreadPerCall = uint64_t(1) << 16;
constexpr uint32_t kMaxUnitsPerCall = 16;
/// How hard zstd works on a result: level -1 (CodecEffort::fast), which the server decodes as
/// it decodes level 3. On a default 512x512, 256-spp job it saved the worker 0.2-0.37 CPU-s
/// for 1.1 % more bytes per result (BENCHMARKS.md, "The farm's overhead on one job").
constexpr CodecEffort kUploadEffort = CodecEffort::fast;

}  // namespace

FarmWorker::FarmWorker(const FarmWorkerConfig& config, StopSignal& stop)
    : config_(config),
      stop_(stop),
      client_(config.server, config.token, config.tls),
      bundles_(config.cache_dir.empty() ? BundleCache::default_dir() : config.cache_dir),
      arena_(config.threads > 0 ? config.threads : tbb::task_arena::automatic) {}

int FarmWorker::run() {
  if (fault_flip_bit_requested()) {
    log("TESSERA_FAULT_FLIP_BIT=1: one bit of every result is flipped (a test seam)");
  }
  log("serving " + config_.server + " with " + std::to_string(threads()) +
      " thread(s), bundle cache " + bundles_.dir().string());
  try {
    while (!stop_.requested()) {
      try {
        if (worker_id_ == 0) register_worker();
        lease_and_render();
        if (unreachable_) log("server reachable again");
        unreachable_ = false;
        backoff_.reset();
      } catch (const Transient& e) {
        if (!unreachable_ && !stop_.requested()) log(std::string(e.what()) + "; retrying");
        unreachable_ = true;
        client_.pause_until_reconnected(backoff_.next(), stop_);
      } catch (const UnknownWorker& e) {
        log(std::string(e.what()) + "; registering again");
        worker_id_ = 0;
      } catch (const Fatal&) {
        throw;
      } catch (const std::exception& e) {
        // Unexpected (out of memory, a full cache disk): keep serving after a pause.
        log(std::string("unexpected error: ") + e.what() + "; retrying");
        stop_.wait_for(backoff_.next());
      }
    }
  } catch (const Fatal& e) {
    log(e.what());
    return 1;
  }
  // What was rendered is delivered before the worker says it leaves.
  try {
    finish_delivery();
  } catch (const Fatal& e) {
    log(e.what());
    return 1;
  }
  deregister();
  log("stopped after delivering " + std::to_string(units_uploaded_) + " unit(s), " +
      std::to_string(result_bytes_) + " result bytes" +
      (units_uploaded_ ? " (" + std::to_string(result_bytes_ / units_uploaded_) + " per unit)"
                       : std::string()));
  return 0;
}

int FarmWorker::threads() const {
  return config_.threads > 0 ? config_.threads : tbb::info::default_concurrency();
}

void FarmWorker::register_worker() {
  v1::RegisterRequest request;
  request.set_name(config_.name.empty() ? default_name() : config_.name);
  request.set_threads(uint32_t(threads()));
  if (isa_.empty()) isa_ = probe_isa();
  request.set_isa(isa_);
  request.set_version(renderer_build());
  v1::RegisterResponse response;
  check(client_.register_worker(request, &response), "Register");
  worker_id_ = response.worker_id();
  log("registered as worker " + std::to_string(worker_id_) + " (" + request.name() + ")");
}

uint32_t FarmWorker::units_per_call() const {
  if (last_unit_samples_ == 0) return 1;
  const uint64_t want = uint64_t(threads()) * kSamplesPerThreadPerCall / last_unit_samples_;
  return uint32_t(std::clamp<uint64_t>(want, 1, kMaxUnitsPerCall));
}

void FarmWorker::lease_and_render() {
  deliveries_.rethrow_if_failed();
  v1::LeaseUnitRequest request;
  request.set_worker_id(worker_id_);
  request.set_wait_ms(kLeaseWaitMs);
  request.set_max_units(units_per_call());
  // The last call's results may still be on their way: their leases are not to come back.
  const std::vector<std::string> delivering = deliveries_.in_flight();
  for (const std::string& id : delivering) request.add_delivering(id);
  v1::LeaseUnitResponse lease;
  const grpc::Status status = client_.lease(request, &lease, stop_);
  if (stop_.requested()) {
    // The results on their way arrive first, so that no lease handed back below is one of
    // theirs (a server answers every lease the worker holds to lease_now).
    finish_delivery();
    // Units leased as the signal arrived go straight back. When the signal cancelled the
    // long poll, the server may still have granted leases the reply never brought: ask once
    // more (the server answers with the leases this worker holds) and hand those back too,
    // rather than leave the units idle until their leases expire.
    if (!status.ok()) {
      lease.Clear();
      if (!client_.lease_now(worker_id_, &lease).ok()) return;
    }
    for (const HeldUnit& h : held_units(lease)) release(h.lease_id, false, "worker stopping");
    return;
  }
  check(status, "LeaseUnit");
  std::vector<HeldUnit> held = held_units(lease);
  if (held.empty()) return;
  // A server from before `delivering` answers those leases too: they are not rendered again.
  // When nothing else came, the delivery is awaited before the next call asks again.
  std::erase_if(held, [&](const HeldUnit& h) {
    return std::find(delivering.begin(), delivering.end(), h.lease_id) != delivering.end();
  });
  if (held.empty()) {
    deliveries_.wait();
    return;
  }
  const v1::WorkUnit& first = held.front().unit;
  last_unit_samples_ = uint64_t(std::max(0, first.x1() - first.x0())) *
                       uint64_t(std::max(0, first.y1() - first.y0())) *
                       (first.sample_end() - first.sample_begin());
  const milliseconds interval(std::max<uint32_t>(50, lease.heartbeat_interval_ms()));
  // Every lease of the call is renewed while any unit of it renders: those waiting their turn
  // and those rendered and waiting for the upload. gone[i]: the server said lease i is gone.
  std::vector<char> gone(held.size(), 0);
  std::vector<v1::UploadResultRequest> results;
  for (size_t i = 0; i < held.size(); ++i) {
    if (stop_.requested()) {
      // The unit in hand was finished; the others go back.
      release(held[i].lease_id, false, "worker stopping");
      continue;
    }
    if (gone[i]) {
      log("job " + std::to_string(held[i].unit.job_id()) +
          ": lease gone (expired or job ended) before its turn; unit dropped");
      continue;
    }
    const auto heartbeat = [&, i] {
      // Every lease still held, in one call (a server from before lease_ids answers one).
      std::vector<size_t> live;
      for (size_t j = 0; j < held.size(); ++j) {
        if (!gone[j]) live.push_back(j);
      }
      const std::vector<LeaseCheck> checks = heartbeat_leases(held, live, interval);
      LeaseCheck own = LeaseCheck::valid;
      for (size_t k = 0; k < live.size(); ++k) {
        if (checks[k] == LeaseCheck::gone) gone[live[k]] = 1;
        if (live[k] == i) own = checks[k];
      }
      return own;
    };
    try {
      if (std::optional<v1::UploadResultRequest> r = render(held[i], heartbeat, interval)) {
        results.push_back(std::move(*r));
      }
    } catch (const UnitFailure& e) {
      log("job " + std::to_string(held[i].unit.job_id()) + ": " + e.what() +
          "; handing the unit back");
      release(held[i].lease_id, true, e.what());
    }
  }
  deliveries_.start(std::move(results));
}

void FarmWorker::finish_delivery() {
  try {
    deliveries_.wait();
  } catch (const Fatal&) {
    throw;
  } catch (const std::exception& e) {
    log(e.what());
  }
}

std::vector<LeaseCheck> FarmWorker::heartbeat_leases(const std::vector<HeldUnit>& held,
                                                     const std::vector<size_t>& live,
                                                     milliseconds interval) {
  if (live.size() <= 1) {
    std::vector<LeaseCheck> out;
    for (size_t j : live) out.push_back(heartbeat_lease(held[j].lease_id, interval));
    return out;
  }
  v1::HeartbeatRequest request;
  request.set_worker_id(worker_id_);
  request.set_lease_id(held[live.front()].lease_id);
  for (size_t j : live) request.add_lease_ids(held[j].lease_id);
  v1::HeartbeatResponse response;
  const grpc::Status status =
      client_.heartbeat(request, &response, std::max(interval, milliseconds(5000)));
  std::vector<LeaseCheck> out(live.size(), LeaseCheck::unreachable);
  if (!status.ok()) return out;
  if (size_t(response.leases_size()) == live.size()) {
    for (size_t k = 0; k < live.size(); ++k) {
      out[k] = response.leases(int(k)).valid() ? LeaseCheck::valid : LeaseCheck::gone;
    }
    return out;
  }
  out[0] = response.valid() ? LeaseCheck::valid : LeaseCheck::gone;
  for (size_t k = 1; k < live.size(); ++k) {
    out[k] = heartbeat_lease(held[live[k]].lease_id, interval);
  }
  return out;
}

LeaseCheck FarmWorker::heartbeat_lease(const std::string& lease_id, milliseconds interval) {
  v1::HeartbeatRequest request;
  request.set_worker_id(worker_id_);
  request.set_lease_id(lease_id);
  v1::HeartbeatResponse response;
  const grpc::Status status =
      client_.heartbeat(request, &response, std::max(interval, milliseconds(5000)));
  if (!status.ok()) return LeaseCheck::unreachable;
  return response.valid() ? LeaseCheck::valid : LeaseCheck::gone;
}

std::shared_ptr<const Renderer> FarmWorker::renderer_for(const v1::WorkUnit& unit, bool& built) {
  const std::string key = unit.bundle_sha256() + "/" + unit.options().SerializeAsString();
  built = false;
  return renderers_.get(key, [&] {
    built = true;
    std::optional<wire::BundleContents> bundle;
    try {
      bundle = bundles_.get(unit.bundle_sha256());
    } catch (const wire::BundleError& e) {
      throw UnitFailure(e.what());
    }
    if (!bundle) bundle = fetch_bundle(unit.bundle_sha256());
    try {
      const Scene scene = wire::parse_bundle_scene(*bundle);
      const JobOptions options = wire::options_from_proto(unit.options());
      log("job " + std::to_string(unit.job_id()) + ": building the renderer for " +
          bundle->scene_file);
      return std::make_unique<Renderer>(scene, options);
    } catch (const SceneError& e) {
      throw UnitFailure(e.what());
    } catch (const std::bad_alloc&) {
      // The job's failure says what ran out, not "std::bad_alloc".
      throw UnitFailure("out of memory building the scene " + bundle->scene_file +
                        " (its meshes, textures and acceleration structure)");
    } catch (const std::exception& e) {
      // Bad options, or the renderer refusing the scene (an ISA this CPU lacks, ...).
      throw UnitFailure(e.what());
    }
  });
}

wire::BundleContents FarmWorker::fetch_bundle(const std::string& sha256) {
  v1::FetchBundleRequest request;
  request.set_sha256(sha256);
  v1::FetchBundleResponse response;
  check(client_.fetch_bundle(request, &response), "FetchBundle");
  try {
    wire::BundleContents bundle = wire::bundle_from_proto(response.bundle());
    bundles_.put(sha256, bundle);  // checks the hash
    return bundle;
  } catch (const wire::BundleError& e) {
    throw UnitFailure(e.what());
  }
}

std::optional<v1::UploadResultRequest> FarmWorker::render(
    const HeldUnit& held, const std::function<LeaseCheck()>& heartbeat, milliseconds interval) {
  const v1::WorkUnit& unit = held.unit;
  bool built = false;
  const std::shared_ptr<const Renderer> renderer = renderer_for(unit, built);
  const TileRect tile{unit.x0(), unit.y0(), unit.x1(), unit.y1()};
  // Building the renderer may have taken a while: renew the leases before rendering.
  if (built && heartbeat() == LeaseCheck::gone) {
    log("job " + std::to_string(unit.job_id()) + ": lease gone while preparing; unit dropped");
    return std::nullopt;
  }
  const UnitRenderResult rendered = render_unit(*renderer, arena_, tile, unit.sample_begin(),
                                                unit.sample_end(), heartbeat, interval, stop_);
  switch (rendered.outcome) {
    case UnitOutcome::lease_lost:
      log("job " + std::to_string(unit.job_id()) + ": lease gone (expired or job ended); unit dropped");
      return std::nullopt;
    case UnitOutcome::abandoned:
      release(held.lease_id, false, "worker stopping");
      return std::nullopt;
    case UnitOutcome::rendered:
      break;
  }
  v1::UploadResultRequest request;
  request.set_worker_id(worker_id_);
  request.set_lease_id(held.lease_id);
  request.set_job_id(unit.job_id());
  request.set_tile(unit.tile());
  request.set_batch(unit.batch());
  const bool faulty = fault_flip_bit_requested();  // a test seam (fault_seam.h)
  const Accumulation flipped = faulty ? with_one_bit_flipped(rendered.result) : Accumulation();
  request.set_accumulation(encode_accumulation(faulty ? flipped : rendered.result, kUploadEffort));
  request.set_isa(renderer->isa());
  milliseconds render_ms = rendered.elapsed;
  // A denoise job's unit over the guides' first samples: its guides too, as a local render's
  // (their time counts in the unit's, which sizes the worker's leases).
  if (unit.guide_sample_end() > unit.sample_begin()) {
    const auto start = std::chrono::steady_clock::now();
    GuideTile guides;
    arena_.execute([&] {
      guides = renderer->render_guides(tile, unit.sample_begin(),
                                       std::min(unit.guide_sample_end(), unit.sample_end()));
    });
    request.set_guides(encode_guide_tile(guides, kUploadEffort));
    render_ms += std::chrono::duration_cast<milliseconds>(std::chrono::steady_clock::now() - start);
  }
  request.set_render_ms(uint32_t(render_ms.count()));
  return request;
}

void FarmWorker::upload_all(std::vector<v1::UploadResultRequest>& results) {
  if (results.empty()) return;
  if (results.size() == 1) {
    upload(results.front());
    return;
  }
  v1::UploadResultsRequest request;
  request.set_worker_id(results.front().worker_id());  // the id the units were leased under
  for (v1::UploadResultRequest& r : results) *request.add_results() = std::move(r);
  const auto give_up = std::chrono::steady_clock::now() + kUploadGiveUp;
  Backoff backoff;
  for (;;) {
    v1::UploadResultsResponse response;
    const grpc::Status status = client_.upload_all(request, &response);
    if (status.ok()) {
      for (int i = 0; i < request.results_size() && i < response.results_size(); ++i) {
        const v1::UploadResultRequest& r = request.results(i);
        ++units_uploaded_;
        result_bytes_ += r.accumulation().size();
        if (!response.results(i).accepted()) {
          log("job " + std::to_string(r.job_id()) + ": result dropped by the server: " +
              response.results(i).reason());
        }
      }
      return;
    }
    if (status.error_code() == grpc::StatusCode::UNIMPLEMENTED) {
      // A server from before batched calls: one call per result.
      for (const v1::UploadResultRequest& r : request.results()) upload(r);
      return;
    }
    if (!is_transient(status.error_code())) {
      try {
        check(status, "UploadResults");  // throws: fatal, unknown worker, or a unit failure
      } catch (const UnitFailure& e) {
        // The server refused the call (none of its results stored): hand the units back.
        log(std::string(e.what()) + "; handing " + std::to_string(request.results_size()) +
            " unit(s) back");
        for (const v1::UploadResultRequest& r : request.results()) {
          release(r.lease_id(), true, e.what());
        }
        return;
      }
    }
    if (stop_.count() >= 2 || std::chrono::steady_clock::now() > give_up) {
      log("giving up delivering " + std::to_string(request.results_size()) + " results: " +
          wire::status_line(status));
      return;
    }
    // A first signal does not end the pause: results in hand are still delivered.
    client_.pause_until_reconnected(backoff.next(), stop_, 2);
  }
}

void FarmWorker::upload(const v1::UploadResultRequest& request) {
  const auto give_up = std::chrono::steady_clock::now() + kUploadGiveUp;
  Backoff backoff;
  for (;;) {
    v1::UploadResultResponse response;
    const grpc::Status status = client_.upload(request, &response);
    if (status.ok()) {
      ++units_uploaded_;
      result_bytes_ += request.accumulation().size();
      if (!response.accepted()) {
        log("job " + std::to_string(request.job_id()) + ": result dropped by the server: " +
            response.reason());
      }
      return;
    }
    if (!is_transient(status.error_code())) {
      check(status, "UploadResult");  // throws: fatal, unknown worker, or a unit failure
    }
    if (stop_.count() >= 2 || std::chrono::steady_clock::now() > give_up) {
      log("job " + std::to_string(request.job_id()) + ": giving up delivering a result: " +
          wire::status_line(status));
      return;
    }
    client_.pause_until_reconnected(backoff.next(), stop_, 2);
  }
}

void FarmWorker::deregister() {
  if (worker_id_ == 0) return;
  v1::DeregisterRequest request;
  request.set_worker_id(worker_id_);
  v1::DeregisterResponse response;
  const grpc::Status status = client_.deregister(request, &response);
  if (!status.ok()) log("Deregister: " + wire::status_line(status));
}

void FarmWorker::release(const std::string& lease_id, bool failed, const std::string& message) {
  v1::ReleaseUnitRequest request;
  request.set_worker_id(worker_id_);
  request.set_lease_id(lease_id);
  request.set_reason(failed ? v1::ReleaseUnitRequest::REASON_FAILED
                            : v1::ReleaseUnitRequest::REASON_SHUTDOWN);
  request.set_message(message);
  v1::ReleaseUnitResponse response;
  const grpc::Status status = client_.release(request, &response);
  if (!status.ok()) log("ReleaseUnit: " + wire::status_line(status) + " (the lease will expire)");
}

}  // namespace tessera::farm
