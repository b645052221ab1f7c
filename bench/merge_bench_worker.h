// tessera-bench-merge (merge_throughput.cpp): the simulated workers, speaking the worker
// protocol over real gRPC, and the channels and deadlines of their calls.
#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <latch>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "merge_bench_results.h"
#include "merge_bench_run.h"

namespace tessera::bench_merge {

/// The farm's channel settings (wire::make_channel's), plus a local subchannel pool when each
/// simulated worker must have its own TCP connection as separate worker processes would:
/// otherwise gRPC shares one connection between channels with equal arguments.
std::shared_ptr<grpc::Channel> make_channel(const std::string& address, bool own_connection);

void check_status(const grpc::Status& status, const std::string& call);

/// Deadlines: the worker's own (docs/farm.md, "gRPC"), except uploads (120 s there): a run is
/// bounded, so an upload that takes 60 s is already a failure worth reporting.
constexpr auto kCallTimeout = std::chrono::seconds(10);
constexpr auto kUploadTimeout = std::chrono::seconds(60);

/// State shared by the simulated workers of one run.
struct RunShared {
  uint64_t job_id = 0;
  uint32_t batch_count = 0;
  std::vector<std::atomic<uint8_t>> acked;  ///< per unit (tile * batches + batch): times accepted
  std::atomic<bool> job_ended{false};
  std::atomic<bool> stop{false};  ///< time bound reached or a worker failed
  std::mutex error_mu;
  std::string error;  ///< first failure (guarded by error_mu)

  explicit RunShared(size_t units) : acked(units) {}
  void fail(const std::string& what) {
    {
      std::lock_guard lock(error_mu);
      if (error.empty()) error = what;
    }
    stop = true;
  }
};

/// One simulated worker: Register, then LeaseUnit -> UploadResult until the job ends (or the
/// run is stopped, when a held unit is handed back with ReleaseUnit SHUTDOWN).
void simulated_worker(int index, std::shared_ptr<grpc::Channel> channel, const Options& options,
                      const ResultBank& bank, RunShared& shared, std::latch& registered,
                      std::latch& go, WorkerTally& tally);

}  // namespace tessera::bench_merge
