// `tessera cancel JOB`: stops a queued or running job (its leases are dropped; what was merged
// stays readable).
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "command_support.h"
#include "json_view.h"

namespace tessera::client {
namespace {

int cancel(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::JobInfo job = client.cancel(job_id);
    if (g.json) {
      std::cout << to_json(job).dump() << std::endl;
    } else {
      std::cout << "job " << job.id() << " cancelled\n";
    }
    return 0;
  });
}

}  // namespace

Command add_cancel_command(CLI::App& app, GlobalOptions& g) {
  const auto job_id = std::make_shared<uint64_t>(0);
  CLI::App* cmd = app.add_subcommand("cancel", "Cancel a job");
  add_job_argument(cmd, *job_id);
  add_json_flag(cmd, g);
  return {cmd, [&g, job_id] { return cancel(g, *job_id); }};
}

}  // namespace tessera::client
