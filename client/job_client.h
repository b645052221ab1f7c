// The CLI's side of tessera.v1.JobService: one method per RPC, each with a deadline and the bearer
// token. Failures throw ClientError with a one-line reason.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "tessera/v1/job_service.grpc.pb.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/transport_security.h"

namespace tessera::client {

class ClientError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JobClient {
 public:
  /// `timeout` is the deadline of each short call; submit and image downloads get at least
  /// kTransferTimeout (they move whole scene bundles and images).
  JobClient(const std::string& server, std::string token, const wire::ClientTls& tls,
            std::chrono::milliseconds timeout);

  static constexpr std::chrono::milliseconds kTransferTimeout{300'000};

  v1::JobInfo submit(const v1::SubmitJobRequest& request);
  v1::JobInfo get(uint64_t job_id);
  /// One page of ListJobs (job_service.proto): the caller follows next_before_id for more.
  v1::ListJobsResponse list(const v1::ListJobsRequest& request);
  v1::JobInfo cancel(uint64_t job_id);
  /// `denoised`: the denoised image of a job submitted with --denoise.
  v1::GetImageResponse image(uint64_t job_id, v1::ImageFormat format, bool denoised = false);
  v1::ListWorkersResponse workers();
  /// Ends the worker's quarantine (WorkerService.ReleaseWorker: the token must be the server's
  /// worker token); returns the worker's name.
  std::string release_worker(uint64_t worker_id);

  /// What the last get() or list() answer said of the server's store: its one-line damage
  /// report when the server found its database damaged (it hands out no more work), else "".
  const std::string& store_damage() const { return store_damage_; }

  /// Streams the job's updates to `on_update` until the job is final; returns the last one.
  /// Each stream call has a deadline (kWatchSegment); when it passes, the watch continues with
  /// a new call, so a watch may last as long as the job; a server restart is ridden out.
  v1::JobInfo watch(uint64_t job_id, const std::function<void(const v1::JobInfo&)>& on_update);

  static constexpr std::chrono::milliseconds kWatchSegment{60'000};
  /// How long watch() keeps reconnecting to an unreachable server (a restart) before failing.
  static constexpr std::chrono::milliseconds kWatchReconnect{60'000};

 private:
  void prepare(class grpc::ClientContext& context, std::chrono::milliseconds timeout) const;

  std::string server_;
  std::string token_;
  std::chrono::milliseconds timeout_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::JobService::Stub> stub_;
  std::string store_damage_;
};

/// "queued", "running", "done", "failed", "cancelled".
std::string state_name(v1::JobState state);
bool is_final(v1::JobState state);

}  // namespace tessera::client
