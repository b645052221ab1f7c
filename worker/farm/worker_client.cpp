#include "worker_client.h"

#include "wire/rpc_channel.h"

namespace tessera::farm {
namespace {

using std::chrono::milliseconds;

/// Deadlines, milliseconds. Bundles and results can be large (tens of MB): generous.
constexpr milliseconds kRegisterTimeout{10'000};
constexpr milliseconds kLeaseMargin{10'000};
constexpr milliseconds kFetchTimeout{300'000};
constexpr milliseconds kUploadTimeout{120'000};
constexpr milliseconds kReleaseTimeout{10'000};

}  // namespace

grpc::ChannelArguments worker_channel_arguments() {
  return wire::channel_arguments(kWorkerReconnect);
}

WorkerClient::WorkerClient(const std::string& server, std::string token, const wire::ClientTls& tls)
    : token_(std::move(token)),
      channel_(wire::make_channel(server, tls, worker_channel_arguments())),
      stub_(v1::WorkerService::NewStub(channel_)) {}

grpc::Status WorkerClient::noted(grpc::Status status) {
  // Read right after the call failed: a pause that follows ends once the channel connects, and
  // not if it never was unconnected (a busy store answers UNAVAILABLE over a live connection).
  if (!status.ok()) unconnected_at_failure_ = channel_->GetState(false) != GRPC_CHANNEL_READY;
  return status;
}

bool WorkerClient::pause_until_reconnected(milliseconds duration, const StopSignal& stop,
                                           int stop_signals) {
  const auto end = std::chrono::system_clock::now() + duration;
  // try_to_connect: an idle channel starts connecting, so that the pause can end early at all.
  grpc_connectivity_state state = channel_->GetState(/*try_to_connect=*/true);
  bool seen_unconnected = unconnected_at_failure_.load() || state != GRPC_CHANNEL_READY;
  while (stop.count() < stop_signals) {
    if (state == GRPC_CHANNEL_READY && seen_unconnected) return true;
    const auto now = std::chrono::system_clock::now();
    if (now >= end) return false;
    // Wakes at the channel's next change of state, or after kStopPoll to look at `stop`.
    if (channel_->WaitForStateChange(state, std::min(end, now + kStopPoll))) {
      state = channel_->GetState(/*try_to_connect=*/true);
      if (state != GRPC_CHANNEL_READY) seen_unconnected = true;
    }
  }
  return false;
}

void WorkerClient::prepare(grpc::ClientContext& context, milliseconds timeout) const {
  wire::prepare_context(context, token_, timeout);
}

grpc::Status WorkerClient::register_worker(const v1::RegisterRequest& request,
                                           v1::RegisterResponse* response) {
  grpc::ClientContext context;
  prepare(context, kRegisterTimeout);
  context.set_wait_for_ready(true);
  return noted(stub_->Register(&context, request, response));
}

grpc::Status WorkerClient::lease(const v1::LeaseUnitRequest& request,
                                 v1::LeaseUnitResponse* response, StopSignal& stop) {
  grpc::ClientContext context;
  prepare(context, milliseconds(request.wait_ms()) + kLeaseMargin);
  context.set_wait_for_ready(true);
  stop.set_cancellable(&context);
  grpc::Status status = noted(stub_->LeaseUnit(&context, request, response));
  stop.set_cancellable(nullptr);
  return status;
}

grpc::Status WorkerClient::lease_now(int64_t worker_id, v1::LeaseUnitResponse* response) {
  v1::LeaseUnitRequest request;
  request.set_worker_id(worker_id);
  request.set_wait_ms(0);
  request.set_max_units(1);
  grpc::ClientContext context;
  prepare(context, kLeaseMargin);
  return noted(stub_->LeaseUnit(&context, request, response));
}

grpc::Status WorkerClient::heartbeat(const v1::HeartbeatRequest& request,
                                     v1::HeartbeatResponse* response, milliseconds timeout) {
  grpc::ClientContext context;
  prepare(context, timeout);
  return noted(stub_->Heartbeat(&context, request, response));
}

grpc::Status WorkerClient::fetch_bundle(const v1::FetchBundleRequest& request,
                                        v1::FetchBundleResponse* response) {
  grpc::ClientContext context;
  prepare(context, kFetchTimeout);
  return noted(stub_->FetchBundle(&context, request, response));
}

grpc::Status WorkerClient::upload(const v1::UploadResultRequest& request,
                                  v1::UploadResultResponse* response) {
  grpc::ClientContext context;
  prepare(context, kUploadTimeout);
  return noted(stub_->UploadResult(&context, request, response));
}

grpc::Status WorkerClient::upload_all(const v1::UploadResultsRequest& request,
                                      v1::UploadResultsResponse* response) {
  grpc::ClientContext context;
  prepare(context, kUploadTimeout);
  return noted(stub_->UploadResults(&context, request, response));
}

grpc::Status WorkerClient::release(const v1::ReleaseUnitRequest& request,
                                   v1::ReleaseUnitResponse* response) {
  grpc::ClientContext context;
  prepare(context, kReleaseTimeout);
  return noted(stub_->ReleaseUnit(&context, request, response));
}

grpc::Status WorkerClient::deregister(const v1::DeregisterRequest& request,
                                      v1::DeregisterResponse* response) {
  grpc::ClientContext context;
  prepare(context, kReleaseTimeout);
  return noted(stub_->Deregister(&context, request, response));
}

}  // namespace tessera::farm
