// What `tessera status` says about the renderer builds that rendered a job.
#pragma once

#include <string>

#include "tessera/v1/job.pb.h"

namespace tessera::client {

/// One "  builds    BUILD" line per renderer build whose results the job accepted (none before
/// the first), and, when there is more than one, a warning line: the image is then not one
/// build's bits (docs/design.md, "The determinism contract"); then a "  pinned    " line with
/// the build the job is pinned to (or that it is not: --any-build), and a "  waiting   no online
/// worker of build X" line when no online worker is of its build.
std::string renderer_builds_text(const v1::JobInfo& job);
/// The job's state name, followed by " (N renderer builds)" when several rendered it and
/// " (waiting for its build)" when no online worker is of the build it is pinned to.
std::string state_text(const v1::JobInfo& job);

}  // namespace tessera::client
