#include "build_text.h"

namespace tessera::client {

std::string renderer_builds_text(const v1::JobInfo& job) {
  std::string out;
  for (const std::string& build : job.renderer_builds()) out += "  builds    " + build + "\n";
  if (job.renderer_builds_size() > 1) {
    out += "  warning   " + std::to_string(job.renderer_builds_size()) +
           " renderer builds rendered this job: its pixels are not one build's bits (run one "
           "build on every worker)\n";
  }
  return out;
}

}  // namespace tessera::client
