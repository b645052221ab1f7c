#include "job_service.h"

#include <algorithm>
#include <optional>

#include "proto_convert.h"
#include "rpc_guard.h"
#include "wire/rpc_channel.h"

namespace tessera::server {
namespace {

int64_t job_id_of(uint64_t id) {
  if (id == 0 || id > uint64_t(INT64_MAX)) {
    throw FarmError(ErrorCode::invalid_argument, "job id must be >= 1");
  }
  return int64_t(id);
}

bool is_final_proto(v1::JobState state) {
  return state == v1::JOB_STATE_DONE || state == v1::JOB_STATE_FAILED ||
         state == v1::JOB_STATE_CANCELLED;
}

/// The listing a ListJobsRequest asks for (job_service.proto). Throws FarmError(invalid_argument)
/// naming the field for a limit over kMaxJobPage, a state that is not one, or a cursor past INT64_MAX.
JobQuery job_query(const v1::ListJobsRequest& request) {
  JobQuery query;
  if (request.limit() > kMaxJobPage) {
    throw FarmError(ErrorCode::invalid_argument, "limit must be 0.." + std::to_string(kMaxJobPage) +
                                                     " (0 = " + std::to_string(kMaxJobPage) +
                                                     "), got " + std::to_string(request.limit()));
  }
  query.limit = request.limit() == 0 ? kMaxJobPage : request.limit();
  for (const int wanted : request.states()) {
    const std::optional<JobState> state = from_proto(v1::JobState(wanted));
    if (!state) {
      throw FarmError(ErrorCode::invalid_argument,
                      "states: " + std::to_string(wanted) +
                          " is not a job state (QUEUED, RUNNING, DONE, FAILED or CANCELLED)");
    }
    query.states.push_back(*state);
  }
  if (request.before_id() > uint64_t(INT64_MAX)) {
    throw FarmError(ErrorCode::invalid_argument,
                    "before_id must be a job id or 0, got " + std::to_string(request.before_id()));
  }
  query.before_id = int64_t(request.before_id());
  return query;
}

/// The submitter, for the per-client quota: the peer's address without its port
/// ("ipv4:10.0.0.7"), so every connection from one host counts together.
std::string client_of(const grpc::ServerContext& context) {
  std::string peer = context.peer();
  const size_t colon = peer.rfind(':');
  const size_t first = peer.find(':');
  if (colon != std::string::npos && colon != first) peer.resize(colon);
  return peer;
}

/// Tells the client that the store is damaged (job_service.proto: trailing metadata
/// wire::kStoreDamageMetadata), once the check found damage; metadata values are printable ASCII.
void tell_store_damage(const Coordinator& coordinator, grpc::ServerContext& context) {
  std::string damage = coordinator.store_damage();
  if (damage.empty()) return;
  for (char& c : damage) c = c < 0x20 || c > 0x7e ? '?' : c;
  context.AddTrailingMetadata(wire::kStoreDamageMetadata, damage);
}

/// How long a submit may wait for budget: `max_wait`, or less to answer before the client's
/// deadline.
std::chrono::milliseconds submit_wait(const grpc::ServerContext& context,
                                      std::chrono::milliseconds max_wait) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      context.deadline() - std::chrono::system_clock::now());
  return std::clamp(left - std::chrono::milliseconds(500), std::chrono::milliseconds(0), max_wait);
}

}  // namespace

grpc::Status JobServiceImpl::SubmitJob(grpc::ServerContext* context,
                                       const v1::SubmitJobRequest* request,
                                       v1::SubmitJobResponse* response) {
  return guarded(auth_, *context, "SubmitJob", [&] {
    // The check's memory is reserved from the headers before anything is decoded, and held
    // until the answer (docs/farm.md, "The server's memory").
    const SubmitCost cost = submit_check_cost(request->bundle(), submit_.max_texture_values);
    std::optional<SubmitBudget::Reservation> reservation;
    if (submit_.budget != nullptr) {
      const std::string detail =
          cost.largest_file.empty()
              ? ""
              : "the most for " + cost.largest_file + ": " +
                    std::to_string((cost.largest_file_bytes + (1 << 20) - 1) >> 20) + " MiB";
      reservation.emplace(submit_.budget->reserve(cost.bytes, request->bundle().scene_file(),
                                                  detail, submit_wait(*context, submit_.max_wait)));
    }
    *response->mutable_job() = to_proto(coordinator_.submit(
        request->bundle(), request->options(), request->priority(), client_of(*context)));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                                    v1::JobInfo* response) {
  return guarded(auth_, *context, "GetJob", [&] {
    tell_store_damage(coordinator_, *context);
    *response = to_proto(coordinator_.job(job_id_of(request->job_id())));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::ListJobs(grpc::ServerContext* context,
                                      const v1::ListJobsRequest* request,
                                      v1::ListJobsResponse* response) {
  return guarded(auth_, *context, "ListJobs", [&] {
    tell_store_damage(coordinator_, *context);
    const JobPage page = coordinator_.jobs(job_query(*request));
    for (const JobRecord& job : page.jobs) *response->add_jobs() = to_proto(job);
    response->set_total(page.total);
    response->set_next_before_id(uint64_t(page.next_before_id));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::CancelJob(grpc::ServerContext* context,
                                       const v1::CancelJobRequest* request,
                                       v1::JobInfo* response) {
  return guarded(auth_, *context, "CancelJob", [&] {
    *response = to_proto(coordinator_.cancel(job_id_of(request->job_id())));
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::DeleteJob(grpc::ServerContext* context,
                                       const v1::DeleteJobRequest* request,
                                       v1::DeleteJobResponse* response) {
  return guarded(auth_, *context, "DeleteJob", [&] {
    coordinator_.remove(job_id_of(request->job_id()));
    response->set_job_id(request->job_id());
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::WatchJob(grpc::ServerContext* context,
                                      const v1::WatchJobRequest* request,
                                      grpc::ServerWriter<v1::JobInfo>* writer) {
  return guarded(auth_, *context, "WatchJob", [&]() -> grpc::Status {
    const int64_t job_id = job_id_of(request->job_id());
    const auto interval =
        std::chrono::milliseconds(request->min_interval_ms() == 0 ? 250 : request->min_interval_ms());
    ChangeNotifier& changes = coordinator_.changes();
    uint64_t seen = changes.version();
    v1::JobInfo info = to_proto(coordinator_.job(job_id));
    std::string last = info.SerializeAsString();
    if (!writer->Write(info)) return {grpc::StatusCode::CANCELLED, "client went away"};
    auto last_write = std::chrono::steady_clock::now();
    while (!is_final_proto(info.state())) {
      if (context->IsCancelled()) return {grpc::StatusCode::CANCELLED, "client went away"};
      if (changes.stopped()) return {grpc::StatusCode::UNAVAILABLE, "server shutting down"};
      seen = changes.wait(seen, std::chrono::milliseconds(1000));
      // Rate limit: at most one message per interval (the job may change thousands of times),
      // except the final state's, sent as soon as the job has ended: waiting out the interval
      // held every `tessera submit` up to 250 ms after its job was done. Each change in the
      // interval costs a look in memory (job_in_progress), not a store read.
      const auto next = last_write + interval;
      for (auto now = std::chrono::steady_clock::now();
           now < next && coordinator_.job_in_progress(job_id) && !context->IsCancelled() &&
           !changes.stopped();
           now = std::chrono::steady_clock::now()) {
        seen = changes.wait(
            seen, std::chrono::duration_cast<std::chrono::milliseconds>(next - now) + std::chrono::milliseconds(1));
      }
      info = to_proto(coordinator_.job(job_id));
      std::string current = info.SerializeAsString();
      if (current == last) continue;
      if (!writer->Write(info)) return {grpc::StatusCode::CANCELLED, "client went away"};
      last = std::move(current);
      last_write = std::chrono::steady_clock::now();
    }
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::GetImage(grpc::ServerContext* context,
                                      const v1::GetImageRequest* request,
                                      v1::GetImageResponse* response) {
  return guarded(auth_, *context, "GetImage", [&] {
    const v1::ImageFormat format =
        request->format() == v1::IMAGE_FORMAT_UNSPECIFIED ? v1::IMAGE_FORMAT_EXR : request->format();
    if (format != v1::IMAGE_FORMAT_EXR && format != v1::IMAGE_FORMAT_PNG) {
      throw FarmError(ErrorCode::invalid_argument, "unknown image format");
    }
    JobImage image = coordinator_.image(job_id_of(request->job_id()),
                                        format == v1::IMAGE_FORMAT_EXR ? "exr" : "png",
                                        request->denoised());
    response->set_data(std::move(image.bytes));
    response->set_format(format);
    response->set_final(image.final);
    response->set_spp(image.spp);
    response->set_width(image.width);
    response->set_height(image.height);
    return grpc::Status::OK;
  });
}

grpc::Status JobServiceImpl::ListWorkers(grpc::ServerContext* context,
                                         const v1::ListWorkersRequest*,
                                         v1::ListWorkersResponse* response) {
  return guarded(auth_, *context, "ListWorkers", [&] {
    for (const WorkerRecord& w : coordinator_.workers()) {
      *response->add_workers() = to_proto(w, coordinator_.online(w));
    }
    return grpc::Status::OK;
  });
}

}  // namespace tessera::server
