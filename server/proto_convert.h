// Store records to their proto messages.
#pragma once

#include "job_store.h"
#include "tessera/v1/job.pb.h"
#include "tessera/v1/job_service.pb.h"
#include "worker_registry.h"

namespace tessera::server {

v1::JobState to_proto(JobState state);
v1::JobInfo to_proto(const JobRecord& job);
v1::WorkerInfo to_proto(const WorkerRecord& worker, bool online);

}  // namespace tessera::server
