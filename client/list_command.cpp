// `tessera list`: the server's jobs, newest first, one line each (or a JSON array): the newest
// 100, `--limit N` or `--all`, only those in the `--state` states when given. The jobs come in
// pages of at most 1000 (ListJobs' largest) that follow the server's cursor (before_id), so a
// job submitted meanwhile never shows twice or pushes one out.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "build_text.h"
#include "command_support.h"
#include "json_view.h"

namespace tessera::client {
namespace {

constexpr uint32_t kPageJobs = 1000;
constexpr v1::JobState kStates[] = {v1::JOB_STATE_QUEUED, v1::JOB_STATE_RUNNING,
                                    v1::JOB_STATE_DONE, v1::JOB_STATE_FAILED,
                                    v1::JOB_STATE_CANCELLED};

struct ListOptions {
  uint64_t limit = 100;             ///< at most this many jobs, newest first
  bool all = false;                 ///< every job (--limit does not apply)
  std::vector<std::string> states;  ///< names as `tessera status` prints them; empty = all
};

/// The jobs asked for and how many match on the server (0 from a server without the count).
struct Listing {
  std::vector<v1::JobInfo> jobs;
  uint64_t total = 0;
};

v1::JobState state_of(const std::string& name) {
  for (const v1::JobState state : kStates) {
    if (state_name(state) == name) return state;
  }
  throw std::invalid_argument("--state " + name + " is not a job state");  // IsMember checked it
}

Listing fetch(JobClient& client, const ListOptions& o) {
  v1::ListJobsRequest request;
  for (const std::string& name : o.states) request.add_states(state_of(name));
  Listing out;
  for (bool first = true;; first = false) {
    const uint64_t left = o.all ? kPageJobs : o.limit - out.jobs.size();
    request.set_limit(uint32_t(std::min<uint64_t>(kPageJobs, left)));
    v1::ListJobsResponse page = client.list(request);
    if (first) out.total = page.total();
    for (v1::JobInfo& job : *page.mutable_jobs()) out.jobs.push_back(std::move(job));
    if (page.next_before_id() == 0 || (!o.all && out.jobs.size() >= o.limit)) break;
    request.set_before_id(page.next_before_id());
  }
  return out;
}

/// "showing 100 of 2274 jobs (...)" when some matching jobs are not shown; "" otherwise.
std::string summary(const Listing& listing, const ListOptions& o) {
  if (listing.total <= listing.jobs.size()) return "";
  std::string which;
  for (const std::string& name : o.states) which += (which.empty() ? "" : " or ") + name;
  return "showing " + std::to_string(listing.jobs.size()) + " of " +
         std::to_string(listing.total) + (which.empty() ? "" : " " + which) +
         " jobs (--all for every job, --limit N for more)";
}

void print_jobs(const std::vector<v1::JobInfo>& jobs) {
  std::printf("%6s  %-9s  %7s  %8s  %-11s  %-24s  %s\n", "ID", "STATE", "DONE", "PRIORITY",
              "SIZE", "RULE", "SCENE");
  for (const auto& job : jobs) {
    const std::string size =
        std::to_string(job.options().width()) + "x" + std::to_string(job.options().height());
    std::printf("%6llu  %-9s  %6.1f%%  %8d  %-11s  %-24s  %s\n",
                static_cast<unsigned long long>(job.id()), state_text(job).c_str(),
                100.0 * job.progress(), job.priority(), size.c_str(),
                rule_text(job.options()).c_str(), job.scene_file().c_str());
  }
}

int list(const GlobalOptions& g, const ListOptions& o) {
  return guarded([&] {
    JobClient client = connect(g);
    Listing listing;
    try {
      listing = fetch(client, o);
    } catch (const ClientError&) {
      warn_store_damage(client);  // the damage may be why the call failed
      throw;
    }
    warn_store_damage(client);
    const std::string more = summary(listing, o);
    if (g.json) {
      // Scripts read the array alone: the count of jobs left out goes to stderr.
      nlohmann::json out = nlohmann::json::array();
      for (const auto& job : listing.jobs) out.push_back(to_json(job));
      std::cout << out.dump() << std::endl;
      if (!more.empty()) std::cerr << more << std::endl;
    } else {
      print_jobs(listing.jobs);
      if (!more.empty()) std::cout << more << std::endl;
    }
    return 0;
  });
}

}  // namespace

Command add_list_command(CLI::App& app, GlobalOptions& g) {
  CLI::App* cmd = app.add_subcommand("list", "List jobs, newest first");
  const auto o = std::make_shared<ListOptions>();
  CLI::Option* limit = cmd->add_option("--limit", o->limit, "At most N jobs, newest first")
                           ->capture_default_str()
                           ->check(CLI::PositiveNumber);
  cmd->add_flag("--all", o->all, "Every job (all pages)")->excludes(limit);
  std::vector<std::string> names;
  for (const v1::JobState state : kStates) names.push_back(state_name(state));
  cmd->add_option("--state", o->states,
                  "Only jobs in this state; repeat it or separate states with commas for "
                  "several")
      ->delimiter(',')
      ->check(CLI::IsMember(names));
  add_json_flag(cmd, g);
  return {cmd, [&g, o] { return list(g, *o); }};
}

}  // namespace tessera::client
