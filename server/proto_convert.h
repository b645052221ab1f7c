// Store records to their proto messages.
#pragma once

#include <optional>

#include "job_store.h"
#include "tessera/v1/job.pb.h"
#include "tessera/v1/job_service.pb.h"
#include "worker_registry.h"

namespace tessera::server {

v1::JobState to_proto(JobState state);
/// The inverse of to_proto(JobState); nullopt for UNSPECIFIED or a number that is no state.
std::optional<JobState> from_proto(v1::JobState state);
v1::JobInfo to_proto(const JobRecord& job);
v1::WorkerInfo to_proto(const WorkerRecord& worker, bool online);

}  // namespace tessera::server
