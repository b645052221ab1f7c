// `tessera watch JOB`: follows a job with a progress bar (or JSON lines) until it ends; exits 1
// unless it is done.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "command_support.h"

namespace tessera::client {
namespace {

int watch(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::JobInfo last = follow(client, job_id, g.json);
    if (!g.json && last.state() == v1::JOB_STATE_DONE) std::cerr << finished_line(last) << "\n";
    return final_status(last);
  });
}

}  // namespace

Command add_watch_command(CLI::App& app, GlobalOptions& g) {
  const auto job_id = std::make_shared<uint64_t>(0);
  CLI::App* cmd = app.add_subcommand("watch", "Follow a job with a progress bar until it ends");
  add_job_argument(cmd, *job_id);
  add_json_flag(cmd, g);
  return {cmd, [&g, job_id] { return watch(g, *job_id); }};
}

}  // namespace tessera::client
