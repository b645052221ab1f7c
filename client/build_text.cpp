#include "build_text.h"

#include "job_client.h"

namespace tessera::client {

std::string renderer_builds_text(const v1::JobInfo& job) {
  std::string out;
  for (const std::string& build : job.renderer_builds()) out += "  builds    " + build + "\n";
  if (job.renderer_builds_size() > 1) {
    out += "  warning   " + std::to_string(job.renderer_builds_size()) +
           " renderer builds rendered this job: its pixels are not one build's bits (run one "
           "build on every worker)\n";
  }
  if (job.any_build()) {
    out += "  pinned    no: submitted with --any-build (leased to workers of every build)\n";
  } else if (!job.pinned_build().empty()) {
    out += "  pinned    " + job.pinned_build() + "\n";
  }
  if (job.waiting_for_build()) {
    out += "  waiting   no online worker of build " + job.pinned_build() + "\n";
  }
  return out;
}

std::string state_text(const v1::JobInfo& job) {
  std::string out = state_name(job.state());
  if (job.renderer_builds_size() > 1) {
    out += " (" + std::to_string(job.renderer_builds_size()) + " renderer builds)";
  }
  if (job.waiting_for_build()) out += " (waiting for its build)";
  return out;
}

}  // namespace tessera::client
