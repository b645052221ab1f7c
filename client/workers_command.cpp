// `tessera workers`: the registered workers, what each is rendering, how many units it holds
// and its health (or a JSON array).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <iostream>

#include "command_support.h"
#include "json_view.h"

namespace tessera::client {
namespace {

void print_workers(const v1::ListWorkersResponse& workers) {
  std::printf("%4s  %-24s  %-11s  %7s  %-7s  %-22s  %4s  %6s  %5s  %6s  %8s  %s\n", "ID", "NAME",
              "STATE", "THREADS", "ISA", "UNIT", "HELD", "DONE", "LOST", "CHECKS", "MISMATCH",
              "BUILD");
  for (const auto& w : workers.workers()) {
    const std::string unit = w.job_id() == 0 ? "-"
                                             : "job " + std::to_string(w.job_id()) + " t" +
                                                   std::to_string(w.tile()) + " b" +
                                                   std::to_string(w.batch());
    const std::string state = !w.state().empty() ? w.state() : w.online() ? "online" : "offline";
    std::printf("%4llu  %-24s  %-11s  %7u  %-7s  %-22s  %4u  %6llu  %5llu  %6llu  %8llu  %s\n",
                static_cast<unsigned long long>(w.id()), w.name().c_str(), state.c_str(),
                w.threads(), w.isa().empty() ? "-" : w.isa().c_str(), unit.c_str(),
                w.units_held(), static_cast<unsigned long long>(w.units_done()),
                static_cast<unsigned long long>(w.units_lost()),
                static_cast<unsigned long long>(w.checks()),
                static_cast<unsigned long long>(w.mismatches()),
                w.build().empty() ? "-" : w.build().c_str());
    if (w.has_quarantine()) {
      std::printf("      quarantined: %s (release: tessera workers release %llu)\n",
                  w.quarantine().reason().c_str(), static_cast<unsigned long long>(w.id()));
    }
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

int release(const GlobalOptions& g, uint64_t worker_id) {
  return guarded([&] {
    JobClient client = connect(g);
    const std::string name = client.release_worker(worker_id);
    std::printf("worker %llu (%s) released: it may lease work again\n",
                static_cast<unsigned long long>(worker_id), name.c_str());
    return 0;
  });
}

}  // namespace

Command add_workers_command(CLI::App& app, GlobalOptions& g) {
  CLI::App* cmd = app.add_subcommand(
      "workers",
      "List workers: state (online, offline, quarantined), threads, the unit each renders, HELD "
      "(units leased to it now, bounded by about a second of its measured rate), DONE, LOST, "
      "and its spot checks: CHECKS and MISMATCH");
  add_json_flag(cmd, g);
  CLI::App* release_cmd = cmd->add_subcommand(
      "release",
      "End a quarantined worker's quarantine (its name may lease work again); needs the "
      "server's worker token as --token");
  auto worker_id = std::make_shared<uint64_t>(0);
  release_cmd->add_option("id", *worker_id, "The worker's ID (tessera workers)")
      ->required()
      ->check(CLI::Range(uint64_t(1), uint64_t(INT64_MAX)));
  return {cmd, [&g, release_cmd, worker_id] {
            return release_cmd->parsed() ? release(g, *worker_id) : workers(g);
          }};
}

}  // namespace tessera::client
