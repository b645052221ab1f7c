// The worker's side of tessera.v1.WorkerService: one method per RPC, each with its deadline and
// the bearer token. Statuses are returned, not thrown: the worker loop decides what to retry.
#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "stop_signal.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/rpc_channel.h"
#include "wire/transport_security.h"

namespace tessera::farm {

/// gRPC's reconnect backoff on the worker's channel: while the server is down, a connection
/// attempt at least every max_ms x wire::kReconnectJitter = 1.2 s, within the 2 s of
/// docs/farm.md ("Server restart") by which a worker is back after the server returns. Its
/// LeaseUnit and Register calls wait for the connection (wait_for_ready) rather than fail while
/// gRPC is between attempts, and its pauses between tries end when the channel connects
/// (WorkerClient::pause_until_reconnected), so the worker's own Backoff (backoff.h) does not add
/// to it.
inline constexpr wire::ReconnectBackoff kWorkerReconnect{100, 1000, 20'000};

/// The arguments of the worker's channel: wire::channel_arguments(kWorkerReconnect).
grpc::ChannelArguments worker_channel_arguments();

class WorkerClient {
 public:
  WorkerClient(const std::string& server, std::string token, const wire::ClientTls& tls = {});

  /// Waits for the connection (wait_for_ready) within its deadline.
  grpc::Status register_worker(const v1::RegisterRequest& request, v1::RegisterResponse* response);
  /// Long poll: the deadline covers the server's wait (request.wait_ms) plus a margin, and the
  /// call waits for the connection within it (wait_for_ready), so that it goes out as soon as a
  /// restarted server accepts one. The call is cancelled at once when `stop` receives a signal.
  grpc::Status lease(const v1::LeaseUnitRequest& request, v1::LeaseUnitResponse* response,
                     StopSignal& stop);
  /// One LeaseUnit call with wait_ms 0 that no signal cancels (a short deadline): after a long
  /// poll was cancelled, it returns the leases the server may have granted meanwhile (leasing is
  /// idempotent; max_units 1, so every lease held comes back in `leases`, or one new one when
  /// none is held), so that the worker can hand them back instead of leaving them to expire.
  grpc::Status lease_now(int64_t worker_id, v1::LeaseUnitResponse* response);
  grpc::Status heartbeat(const v1::HeartbeatRequest& request, v1::HeartbeatResponse* response,
                         std::chrono::milliseconds timeout);
  grpc::Status fetch_bundle(const v1::FetchBundleRequest& request,
                            v1::FetchBundleResponse* response);
  grpc::Status upload(const v1::UploadResultRequest& request, v1::UploadResultResponse* response);
  grpc::Status upload_all(const v1::UploadResultsRequest& request,
                          v1::UploadResultsResponse* response);
  grpc::Status release(const v1::ReleaseUnitRequest& request, v1::ReleaseUnitResponse* response);
  grpc::Status deregister(const v1::DeregisterRequest& request, v1::DeregisterResponse* response);

  /// The worker's pause between two tries while the server cannot be reached: sleeps up to
  /// `duration` (its Backoff's delay), but ends as soon as the channel is connected if it was not
  /// when this client's last failed call returned, or was seen unconnected during the pause (a
  /// restarted server answers), so that the next call goes out then and not at the end of the
  /// pause; also ends once `stop` has counted `stop_signals` signals (checked every kStopPoll).
  /// Returns true when it ended because the channel connected.
  bool pause_until_reconnected(std::chrono::milliseconds duration, const StopSignal& stop,
                               int stop_signals = 1);
  static constexpr std::chrono::milliseconds kStopPoll{100};

 private:
  void prepare(grpc::ClientContext& context, std::chrono::milliseconds timeout) const;
  /// Returns `status`, noting after a failure whether the channel was connected.
  grpc::Status noted(grpc::Status status);

  std::string token_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::WorkerService::Stub> stub_;
  std::atomic<bool> unconnected_at_failure_{false};
};

}  // namespace tessera::farm
