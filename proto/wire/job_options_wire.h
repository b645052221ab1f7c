// Job options on the wire: the user's overrides and the resolved options, to and from proto.
#pragma once

#include <string>

#include "job/job_options.h"
#include "tessera/v1/job.pb.h"

namespace tessera::wire {

v1::StopRule stop_rule_to_proto(StopRule rule);
StopRule stop_rule_from_proto(v1::StopRule rule);
v1::StopReason stop_reason_to_proto(StopReason reason);
StopReason stop_reason_from_proto(v1::StopReason reason);

JobOverrides overrides_from_proto(const v1::JobRequestOptions& options);
v1::JobRequestOptions overrides_to_proto(const JobOverrides& overrides);

v1::ResolvedJobOptions options_to_proto(const JobOptions& options);
JobOptions options_from_proto(const v1::ResolvedJobOptions& options);

/// The resolved options as one-line JSON with every field, in field order (provenance).
std::string options_to_json(const JobOptions& options);

}  // namespace tessera::wire
