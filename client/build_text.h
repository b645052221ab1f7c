// What `tessera status` says about the renderer builds that rendered a job.
#pragma once

#include <string>

#include "tessera/v1/job.pb.h"

namespace tessera::client {

/// One "  builds    BUILD" line per renderer build whose results the job accepted (none before
/// the first), and, when there is more than one, a warning line: the image is then not one
/// build's bits (docs/design.md, "The determinism contract").
std::string renderer_builds_text(const v1::JobInfo& job);

}  // namespace tessera::client
