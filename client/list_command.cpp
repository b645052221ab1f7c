// `tessera list`: the server's jobs, newest first, one line each (or a JSON array).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "command_support.h"
#include "json_view.h"

namespace tessera::client {
namespace {

void print_jobs(const v1::ListJobsResponse& jobs) {
  std::printf("%6s  %-9s  %7s  %8s  %-11s  %-24s  %s\n", "ID", "STATE", "DONE", "PRIORITY",
              "SIZE", "RULE", "SCENE");
  for (const auto& job : jobs.jobs()) {
    const std::string size =
        std::to_string(job.options().width()) + "x" + std::to_string(job.options().height());
    std::printf("%6llu  %-9s  %6.1f%%  %8d  %-11s  %-24s  %s\n",
                static_cast<unsigned long long>(job.id()), state_name(job.state()).c_str(),
                100.0 * job.progress(), job.priority(), size.c_str(),
                rule_text(job.options()).c_str(), job.scene_file().c_str());
  }
}

int list(const GlobalOptions& g) {
  return guarded([&] {
    JobClient client = connect(g);
    v1::ListJobsResponse jobs;
    try {
      jobs = client.list(0);
    } catch (const ClientError&) {
      warn_store_damage(client);  // the damage may be why the call failed
      throw;
    }
    warn_store_damage(client);
    if (g.json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& job : jobs.jobs()) out.push_back(to_json(job));
      std::cout << out.dump() << std::endl;
    } else {
      print_jobs(jobs);
    }
    return 0;
  });
}

}  // namespace

Command add_list_command(CLI::App& app, GlobalOptions& g) {
  CLI::App* cmd = app.add_subcommand("list", "List jobs, newest first");
  add_json_flag(cmd, g);
  return {cmd, [&g] { return list(g); }};
}

}  // namespace tessera::client
