// tessera.v1.WorkerService over the Coordinator (proto/tessera/v1/worker_service.proto documents
// each call).
#pragma once

#include "coordinator.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/bearer_token.h"

namespace tessera::server {

class WorkerServiceImpl final : public v1::WorkerService::Service {
 public:
  /// Longest LeaseUnit long poll, milliseconds, whatever the worker asks.
  static constexpr uint32_t kMaxLeaseWaitMs = 5000;
  /// Most units one LeaseUnit call leases, and most results one UploadResults call carries.
  static constexpr uint32_t kMaxUnitsPerCall = 64;

  WorkerServiceImpl(Coordinator& coordinator, const wire::BearerTokenCheck& auth)
      : coordinator_(coordinator), auth_(auth) {}

  grpc::Status Register(grpc::ServerContext* context, const v1::RegisterRequest* request,
                        v1::RegisterResponse* response) override;
  grpc::Status LeaseUnit(grpc::ServerContext* context, const v1::LeaseUnitRequest* request,
                         v1::LeaseUnitResponse* response) override;
  grpc::Status Heartbeat(grpc::ServerContext* context, const v1::HeartbeatRequest* request,
                         v1::HeartbeatResponse* response) override;
  grpc::Status FetchBundle(grpc::ServerContext* context, const v1::FetchBundleRequest* request,
                           v1::FetchBundleResponse* response) override;
  grpc::Status UploadResult(grpc::ServerContext* context, const v1::UploadResultRequest* request,
                            v1::UploadResultResponse* response) override;
  grpc::Status UploadResults(grpc::ServerContext* context,
                             const v1::UploadResultsRequest* request,
                             v1::UploadResultsResponse* response) override;
  grpc::Status ReleaseUnit(grpc::ServerContext* context, const v1::ReleaseUnitRequest* request,
                           v1::ReleaseUnitResponse* response) override;
  grpc::Status Deregister(grpc::ServerContext* context, const v1::DeregisterRequest* request,
                          v1::DeregisterResponse* response) override;
  grpc::Status ReleaseWorker(grpc::ServerContext* context, const v1::ReleaseWorkerRequest* request,
                             v1::ReleaseWorkerResponse* response) override;

 private:
  Coordinator& coordinator_;
  const wire::BearerTokenCheck& auth_;
};

}  // namespace tessera::server
