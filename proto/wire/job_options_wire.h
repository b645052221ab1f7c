// Job options on the wire: the user's overrides and the resolved options, to and from proto.
#pragma once

#include <string>

#include "job/job_options.h"
#include "tessera/v1/job.pb.h"

namespace tessera::wire {

JobOverrides overrides_from_proto(const v1::JobRequestOptions& options);
v1::JobRequestOptions overrides_to_proto(const JobOverrides& overrides);

v1::ResolvedJobOptions options_to_proto(const JobOptions& options);
JobOptions options_from_proto(const v1::ResolvedJobOptions& options);

/// The resolved options as one-line JSON with every field, in field order (provenance).
std::string options_to_json(const JobOptions& options);

}  // namespace tessera::wire
