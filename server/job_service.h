// tessera.v1.JobService over the Coordinator (proto/tessera/v1/job_service.proto documents each
// call).
#pragma once

#include <chrono>

#include "coordinator.h"
#include "scene/image_check.h"
#include "submit_budget.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "wire/bearer_token.h"

namespace tessera::server {

/// What SubmitJob checks before it validates a bundle (docs/farm.md, "The server's memory").
struct SubmitChecks {
  /// The memory budget of the checks (--submit-memory-mb); none: no budget.
  SubmitBudget* budget = nullptr;
  /// The most values (width x height x channels) of one image of a bundle (--max-texture-values).
  uint64_t max_texture_values = kMaxImageValues;
  /// How long a submit waits for budget at most (less when the client's deadline is nearer).
  std::chrono::milliseconds max_wait{60'000};
};

class JobServiceImpl final : public v1::JobService::Service {
 public:
  JobServiceImpl(Coordinator& coordinator, const wire::BearerTokenCheck& auth,
                 SubmitChecks submit = {})
      : coordinator_(coordinator), auth_(auth), submit_(submit) {}

  grpc::Status SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                         v1::SubmitJobResponse* response) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                      v1::JobInfo* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                         v1::JobInfo* response) override;
  grpc::Status DeleteJob(grpc::ServerContext* context, const v1::DeleteJobRequest* request,
                         v1::DeleteJobResponse* response) override;
  grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                        grpc::ServerWriter<v1::JobInfo>* writer) override;
  grpc::Status GetImage(grpc::ServerContext* context, const v1::GetImageRequest* request,
                        v1::GetImageResponse* response) override;
  grpc::Status ListWorkers(grpc::ServerContext* context, const v1::ListWorkersRequest* request,
                           v1::ListWorkersResponse* response) override;

 private:
  Coordinator& coordinator_;
  const wire::BearerTokenCheck& auth_;
  const SubmitChecks submit_;
};

}  // namespace tessera::server
