// `tessera workers`: the registered workers, what each is rendering, how many units it holds
// and its health (or a JSON array).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "command_support.h"
#include "json_view.h"

namespace tessera::client {
namespace {

void print_workers(const v1::ListWorkersResponse& workers) {
  std::printf("%4s  %-24s  %-7s  %7s  %-7s  %-22s  %4s  %6s  %5s  %s\n", "ID", "NAME", "STATUS",
              "THREADS", "ISA", "UNIT", "HELD", "DONE", "LOST", "BUILD");
  for (const auto& w : workers.workers()) {
    const std::string unit = w.job_id() == 0 ? "-"
                                             : "job " + std::to_string(w.job_id()) + " t" +
                                                   std::to_string(w.tile()) + " b" +
                                                   std::to_string(w.batch());
    std::printf("%4llu  %-24s  %-7s  %7u  %-7s  %-22s  %4u  %6llu  %5llu  %s\n",
                static_cast<unsigned long long>(w.id()), w.name().c_str(),
                w.online() ? "online" : "offline", w.threads(),
                w.isa().empty() ? "-" : w.isa().c_str(), unit.c_str(), w.units_held(),
                static_cast<unsigned long long>(w.units_done()),
                static_cast<unsigned long long>(w.units_lost()),
                w.build().empty() ? "-" : w.build().c_str());
    if (!w.health_warning().empty()) {
      std::printf("      warning: %s\n", w.health_warning().c_str());
    }
  }
}

int workers(const GlobalOptions& g) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::ListWorkersResponse workers = client.workers();
    if (g.json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& w : workers.workers()) out.push_back(to_json(w));
      std::cout << out.dump() << std::endl;
    } else {
      print_workers(workers);
    }
    return 0;
  });
}

}  // namespace

Command add_workers_command(CLI::App& app, GlobalOptions& g) {
  CLI::App* cmd = app.add_subcommand(
      "workers",
      "List workers: status, threads, the unit each renders, HELD (units leased to it now, "
      "bounded by about a second of its measured rate), DONE and LOST");
  add_json_flag(cmd, g);
  return {cmd, [&g] { return workers(g); }};
}

}  // namespace tessera::client
