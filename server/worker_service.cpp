#include "worker_service.h"

#include <algorithm>

#include "call_trace.h"
#include "rpc_guard.h"
#include "wire/job_options_wire.h"
#include "wire/scene_bundle.h"

namespace tessera::server {
namespace {

int64_t worker_id_of(uint64_t id) {
  if (id == 0 || id > uint64_t(INT64_MAX)) {
    throw FarmError(ErrorCode::invalid_argument, "worker id must be >= 1 (register first)");
  }
  return int64_t(id);
}

}  // namespace

grpc::Status WorkerServiceImpl::Register(grpc::ServerContext* context,
                                         const v1::RegisterRequest* request,
                                         v1::RegisterResponse* response) {
  return guarded(auth_, *context, "Register", [&] {
    WorkerRegistration info{request->name(), request->threads(), request->isa(),
                            request->version()};
    if (info.name.empty()) info.name = context->peer();
    response->set_worker_id(uint64_t(coordinator_.register_worker(info)));
    return grpc::Status::OK;
  });
}

namespace {

void fill_unit(const LeasedUnit& unit, v1::WorkUnit* u) {
  u->set_job_id(uint64_t(unit.lease.job_id));
  u->set_tile(unit.lease.tile);
  u->set_x0(unit.rect.x0);
  u->set_y0(unit.rect.y0);
  u->set_x1(unit.rect.x1);
  u->set_y1(unit.rect.y1);
  u->set_batch(unit.lease.batch);
  u->set_sample_begin(unit.sample_begin);
  u->set_sample_end(unit.sample_end);
  *u->mutable_options() = wire::options_to_proto(unit.options);
  u->set_bundle_sha256(unit.bundle_sha256);
  if (unit.guide_sample_end > 0) u->set_guide_sample_end(unit.guide_sample_end);
}

}  // namespace

grpc::Status WorkerServiceImpl::LeaseUnit(grpc::ServerContext* context,
                                          const v1::LeaseUnitRequest* request,
                                          v1::LeaseUnitResponse* response) {
  const int64_t entered_ns = call_trace::now_ns();
  return guarded(auth_, *context, "LeaseUnit", [&] {
    const auto wait = std::chrono::milliseconds(std::min(request->wait_ms(), kMaxLeaseWaitMs));
    // max_units 0: a worker from before batched leases, answered in the single-unit fields.
    const uint32_t max_units = std::min(request->max_units(), kMaxUnitsPerCall);
    const std::vector<std::string> delivering(request->delivering().begin(),
                                              request->delivering().end());
    const std::vector<LeasedUnit> units =
        coordinator_.lease_units(worker_id_of(request->worker_id()), std::max(1u, max_units),
                                 wait, [context] { return context->IsCancelled(); }, delivering);
    response->set_heartbeat_interval_ms(uint32_t(std::max<int64_t>(50, coordinator_.lease_ms() / 3)));
    response->set_leased(!units.empty());
    if (units.empty()) {
      call_trace::record("lease", entered_ns, call_trace::now_ns(), 0, request->wait_ms());
      return grpc::Status::OK;
    }
    if (max_units == 0) {
      response->set_lease_id(units.front().lease.lease_id);
      response->set_expires_unix_ms(units.front().lease.expires_unix_ms);
      fill_unit(units.front(), response->mutable_unit());
    } else {
      for (const LeasedUnit& unit : units) {
        v1::UnitLease* l = response->add_leases();
        l->set_lease_id(unit.lease.lease_id);
        l->set_expires_unix_ms(unit.lease.expires_unix_ms);
        fill_unit(unit, l->mutable_unit());
      }
    }
    call_trace::record("lease", entered_ns, call_trace::now_ns(), int64_t(units.size()),
                       request->wait_ms(), units.front().lease.lease_id);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::Heartbeat(grpc::ServerContext* context,
                                          const v1::HeartbeatRequest* request,
                                          v1::HeartbeatResponse* response) {
  return guarded(auth_, *context, "Heartbeat", [&] {
    const int64_t worker_id = worker_id_of(request->worker_id());
    if (request->lease_ids().empty()) {
      const std::optional<int64_t> expires = coordinator_.heartbeat(worker_id, request->lease_id());
      response->set_valid(expires.has_value());
      response->set_expires_unix_ms(expires.value_or(0));
      return grpc::Status::OK;
    }
    const std::vector<std::string> ids(request->lease_ids().begin(), request->lease_ids().end());
    const std::vector<std::optional<int64_t>> renewed = coordinator_.heartbeat_all(worker_id, ids);
    for (const std::optional<int64_t>& expires : renewed) {
      v1::LeaseRenewal* r = response->add_leases();
      r->set_valid(expires.has_value());
      r->set_expires_unix_ms(expires.value_or(0));
    }
    response->set_valid(renewed.front().has_value());
    response->set_expires_unix_ms(renewed.front().value_or(0));
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::FetchBundle(grpc::ServerContext* context,
                                            const v1::FetchBundleRequest* request,
                                            v1::FetchBundleResponse* response) {
  return guarded(auth_, *context, "FetchBundle", [&] {
    const std::string bytes = coordinator_.bundle(request->sha256());
    *response->mutable_bundle() = wire::bundle_to_proto(wire::parse_canonical(bytes));
    response->set_sha256(request->sha256());
    return grpc::Status::OK;
  });
}

namespace {

UnitResult result_of(const v1::UploadResultRequest& request, uint64_t worker_id) {
  if (request.job_id() == 0 || request.job_id() > uint64_t(INT64_MAX)) {
    throw FarmError(ErrorCode::invalid_argument, "job id must be >= 1");
  }
  UnitResult result;
  result.worker_id = worker_id_of(worker_id);
  result.lease_id = request.lease_id();
  result.job_id = int64_t(request.job_id());
  result.tile = request.tile();
  result.batch = request.batch();
  result.encoded = request.accumulation();
  result.isa = request.isa();
  result.render_ms = request.render_ms();
  result.guides = request.guides();
  return result;
}

}  // namespace

grpc::Status WorkerServiceImpl::UploadResult(grpc::ServerContext* context,
                                             const v1::UploadResultRequest* request,
                                             v1::UploadResultResponse* response) {
  return guarded(auth_, *context, "UploadResult", [&] {
    const AcceptOutcome outcome =
        coordinator_.upload(result_of(*request, request->worker_id()));
    response->set_accepted(outcome.accepted);
    response->set_reason(outcome.reason);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::UploadResults(grpc::ServerContext* context,
                                              const v1::UploadResultsRequest* request,
                                              v1::UploadResultsResponse* response) {
  const int64_t entered_ns = call_trace::now_ns();
  return guarded(auth_, *context, "UploadResults", [&] {
    if (request->results_size() == 0) {
      throw FarmError(ErrorCode::invalid_argument, "UploadResults carries no result");
    }
    if (uint32_t(request->results_size()) > kMaxUnitsPerCall) {
      throw FarmError(ErrorCode::invalid_argument,
                      "UploadResults carries " + std::to_string(request->results_size()) +
                          " results; at most " + std::to_string(kMaxUnitsPerCall) + " per call");
    }
    std::vector<UnitResult> results;
    for (int i = 0; i < request->results_size(); ++i) {
      const v1::UploadResultRequest& r = request->results(i);
      if (r.worker_id() != 0 && r.worker_id() != request->worker_id()) {
        throw FarmError(ErrorCode::invalid_argument,
                        "result " + std::to_string(i) + " names worker " +
                            std::to_string(r.worker_id()) + ", the call worker " +
                            std::to_string(request->worker_id()));
      }
      results.push_back(result_of(r, request->worker_id()));
    }
    for (const AcceptOutcome& outcome : coordinator_.upload_all(results)) {
      v1::UploadResultResponse* answer = response->add_results();
      answer->set_accepted(outcome.accepted);
      answer->set_reason(outcome.reason);
    }
    call_trace::record("upload", entered_ns, call_trace::now_ns(), request->results_size());
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::ReleaseUnit(grpc::ServerContext* context,
                                            const v1::ReleaseUnitRequest* request,
                                            v1::ReleaseUnitResponse* response) {
  return guarded(auth_, *context, "ReleaseUnit", [&] {
    const ReleaseReason reason = request->reason() == v1::ReleaseUnitRequest::REASON_FAILED
                                     ? ReleaseReason::failed
                                     : ReleaseReason::shutdown;
    const ReleaseOutcome outcome = coordinator_.release(
        worker_id_of(request->worker_id()), request->lease_id(), reason, request->message());
    response->set_released(outcome.released);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::Deregister(grpc::ServerContext* context,
                                           const v1::DeregisterRequest* request,
                                           v1::DeregisterResponse*) {
  return guarded(auth_, *context, "Deregister", [&] {
    coordinator_.deregister(worker_id_of(request->worker_id()));
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::ReleaseWorker(grpc::ServerContext* context,
                                              const v1::ReleaseWorkerRequest* request,
                                              v1::ReleaseWorkerResponse* response) {
  return guarded(auth_, *context, "ReleaseWorker", [&] {
    response->set_name(coordinator_.release_worker(worker_id_of(request->worker_id())));
    return grpc::Status::OK;
  });
}

}  // namespace tessera::server
