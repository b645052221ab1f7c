#include "job_client.h"

#include <grpcpp/grpcpp.h>

#include <optional>
#include <thread>

#include "wire/job_json.h"
#include "wire/rpc_channel.h"

namespace tessera::client {
namespace {

void check(const grpc::Status& status, const std::string& server) {
  if (status.ok()) return;
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
    throw ClientError("cannot reach the server at " + server + " (" + wire::status_line(status) +
                      ")");
  }
  if (status.error_code() == grpc::StatusCode::INVALID_ARGUMENT ||
      status.error_code() == grpc::StatusCode::NOT_FOUND ||
      status.error_code() == grpc::StatusCode::FAILED_PRECONDITION) {
    throw ClientError(status.error_message());
  }
  throw ClientError(wire::status_line(status));
}

/// The server's damage report from a call's trailing metadata (job_service.proto), or "".
std::string store_damage_of(const grpc::ClientContext& context) {
  const auto& trailers = context.GetServerTrailingMetadata();
  const auto it = trailers.find(wire::kStoreDamageMetadata);
  return it == trailers.end() ? "" : std::string(it->second.data(), it->second.size());
}

}  // namespace

std::string state_name(v1::JobState state) { return wire::job_state_name(state); }

bool is_final(v1::JobState state) {
  return state == v1::JOB_STATE_DONE || state == v1::JOB_STATE_FAILED ||
         state == v1::JOB_STATE_CANCELLED;
}

JobClient::JobClient(const std::string& server, std::string token, const wire::ClientTls& tls,
                     std::chrono::milliseconds timeout)
    : server_(server),
      token_(std::move(token)),
      timeout_(timeout),
      channel_(wire::make_channel(server, tls)),
      stub_(v1::JobService::NewStub(channel_)) {}

void JobClient::prepare(grpc::ClientContext& context, std::chrono::milliseconds timeout) const {
  wire::prepare_context(context, token_, timeout);
}

v1::JobInfo JobClient::submit(const v1::SubmitJobRequest& request) {
  grpc::ClientContext context;
  prepare(context, std::max(timeout_, kTransferTimeout));
  v1::SubmitJobResponse response;
  check(stub_->SubmitJob(&context, request, &response), server_);
  return response.job();
}

v1::JobInfo JobClient::get(uint64_t job_id) {
  grpc::ClientContext context;
  prepare(context, timeout_);
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  v1::JobInfo response;
  const grpc::Status status = stub_->GetJob(&context, request, &response);
  store_damage_ = store_damage_of(context);
  check(status, server_);
  return response;
}

v1::ListJobsResponse JobClient::list(const v1::ListJobsRequest& request) {
  grpc::ClientContext context;
  prepare(context, timeout_);
  v1::ListJobsResponse response;
  const grpc::Status status = stub_->ListJobs(&context, request, &response);
  store_damage_ = store_damage_of(context);
  check(status, server_);
  return response;
}

v1::JobInfo JobClient::cancel(uint64_t job_id) {
  grpc::ClientContext context;
  prepare(context, timeout_);
  v1::CancelJobRequest request;
  request.set_job_id(job_id);
  v1::JobInfo response;
  check(stub_->CancelJob(&context, request, &response), server_);
  return response;
}

v1::GetImageResponse JobClient::image(uint64_t job_id, v1::ImageFormat format, bool denoised) {
  grpc::ClientContext context;
  prepare(context, std::max(timeout_, kTransferTimeout));
  v1::GetImageRequest request;
  request.set_job_id(job_id);
  request.set_format(format);
  if (denoised) request.set_denoised(true);
  v1::GetImageResponse response;
  check(stub_->GetImage(&context, request, &response), server_);
  return response;
}

v1::ListWorkersResponse JobClient::workers() {
  grpc::ClientContext context;
  prepare(context, timeout_);
  v1::ListWorkersResponse response;
  check(stub_->ListWorkers(&context, v1::ListWorkersRequest{}, &response), server_);
  return response;
}

std::string JobClient::release_worker(uint64_t worker_id) {
  grpc::ClientContext context;
  prepare(context, timeout_);
  v1::ReleaseWorkerRequest request;
  request.set_worker_id(worker_id);
  v1::ReleaseWorkerResponse response;
  check(v1::WorkerService::NewStub(channel_)->ReleaseWorker(&context, request, &response),
        server_);
  return response.name();
}

v1::JobInfo JobClient::watch(uint64_t job_id,
                             const std::function<void(const v1::JobInfo&)>& on_update) {
  v1::JobInfo last;
  // A server restart breaks the stream: keep trying for kWatchReconnect before failing.
  // (A time point and a flag rather than an optional: GCC 12 warns, wrongly, that the optional's
  // value may be read uninitialized.)
  std::chrono::steady_clock::time_point unreachable_since{};
  bool unreachable = false;
  for (;;) {
    grpc::ClientContext context;
    prepare(context, kWatchSegment);
    v1::WatchJobRequest request;
    request.set_job_id(job_id);
    request.set_min_interval_ms(250);
    auto reader = stub_->WatchJob(&context, request);
    v1::JobInfo info;
    while (reader->Read(&info)) {
      last = info;
      on_update(info);
    }
    const grpc::Status status = reader->Finish();
    if (is_final(last.state())) return last;
    // The segment's deadline passed while the job runs: watch on with a new call.
    if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) continue;
    if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
      const auto now = std::chrono::steady_clock::now();
      if (!unreachable) unreachable_since = now;
      unreachable = true;
      if (now - unreachable_since < kWatchReconnect) {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        continue;
      }
    } else {
      unreachable = false;
    }
    check(status, server_);
    if (status.ok()) return last;  // the server ended the stream without a final state
  }
}

}  // namespace tessera::client
