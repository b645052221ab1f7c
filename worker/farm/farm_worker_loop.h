// FarmWorker: the loop of `tessera-worker --server` (farm_worker.h): it registers, leases units,
// renders them and hands their results to the delivery thread, and reconnects with backoff.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backoff.h"
#include "bundle_cache.h"
#include "deliveries.h"
#include "farm_worker.h"
#include "held_unit.h"
#include "render/renderer.h"
#include "renderer_cache.h"
#include "stop_signal.h"
#include "unit_render.h"
#include "wire/scene_bundle.h"
#include "worker_client.h"

namespace tessera::farm {

class FarmWorker {
 public:
  FarmWorker(const FarmWorkerConfig& config, StopSignal& stop);

  int run();

 private:
  int threads() const;

  void register_worker();

  /// Units to ask for: as many units of the last size seen as make kSamplesPerThreadPerCall
  /// samples per render thread (1 before any unit was seen).
  uint32_t units_per_call() const;

  void lease_and_render();

  /// Waits for the delivery on its way (when stopping): what it threw is logged, a Fatal
  /// error rethrown.
  void finish_delivery();

  /// The leases held[live[k]] renewed in one Heartbeat call (lease_ids); answer k is lease k's.
  /// A server from before lease_ids answers only the first: the others get a call each.
  std::vector<LeaseCheck> heartbeat_leases(const std::vector<HeldUnit>& held,
                                           const std::vector<size_t>& live,
                                           std::chrono::milliseconds interval);

  /// One heartbeat of one lease.
  LeaseCheck heartbeat_lease(const std::string& lease_id, std::chrono::milliseconds interval);

  /// The job's renderer; `built` says whether it had to be made (bundle fetched or read, BVH
  /// built), which may take longer than a heartbeat interval.
  std::shared_ptr<const Renderer> renderer_for(const v1::WorkUnit& unit, bool& built);

  wire::BundleContents fetch_bundle(const std::string& sha256);

  /// Renders one held unit; its upload, or nullopt when the unit was dropped (lease gone) or
  /// handed back (abandoned on a second signal).
  std::optional<v1::UploadResultRequest> render(const HeldUnit& held,
                                                const std::function<LeaseCheck()>& heartbeat,
                                                std::chrono::milliseconds interval);

  /// Delivers the results of one call: one UploadResults call for several (one transaction on
  /// the server), UploadResult for one. Retries while the server is unreachable, as upload().
  /// Runs on the delivery thread (Deliveries).
  void upload_all(std::vector<v1::UploadResultRequest>& results);

  /// Delivers a result, retrying while the server is unreachable (up to kUploadGiveUp, or until
  /// a second signal).
  void upload(const v1::UploadResultRequest& request);

  /// Tells the server this worker is leaving, so that it is listed offline at once; a failure
  /// is only logged (the server then marks it offline after three lease periods).
  void deregister();

  /// Hands a unit back; failures to reach the server are only logged (the lease then expires).
  void release(const std::string& lease_id, bool failed, const std::string& message);

  const FarmWorkerConfig& config_;
  StopSignal& stop_;
  WorkerClient client_;
  BundleCache bundles_;
  RendererCache renderers_;
  tbb::task_arena arena_;
  Backoff backoff_;
  std::atomic<uint64_t> worker_id_ = 0;  ///< set by this thread, read by the delivery thread
  std::string isa_;
  bool unreachable_ = false;
  std::atomic<uint64_t> units_uploaded_ = 0;  ///< results delivered (accepted or dropped)
  std::atomic<uint64_t> result_bytes_ = 0;    ///< their encoded accumulation bytes
  uint64_t last_unit_samples_ = 0;  ///< pixels x samples of the last unit leased
  /// Last: its thread calls upload_all, which uses the members above.
  Deliveries deliveries_{[this](std::vector<v1::UploadResultRequest>& r) { upload_all(r); }};
};

}  // namespace tessera::farm
