#include "merge_bench_report.h"

#include <cstdio>

namespace tessera::bench_merge {

std::string config_name(const RunConfig& c) {
  char text[64];
  std::snprintf(text, sizeof text, "%2d %d %3d %-6s", c.tile, c.batch_spp, c.workers,
                c.shared_channel ? "shared" : "own");
  return text;
}

void print_header() {
  std::printf(
      "tile b   N chan   | units  res/s(client) merged/s(server) | lease p50/p99 ms | upload "
      "p50/p99/max ms | accum B  proto B/res | srv CPU ms/res cli CPU ms/res | srv CPU s listen, "
      "ms/res life | early%% | ok\n");
}

void print_row(const RunResult& r, const char* label) {
  std::printf(
      "%s | %5u %10.0f %12.0f      | %6.2f %7.2f   | %6.2f %7.2f %7.1f  | %7.0f %9.0f  | %8.2f "
      "%12.2f      | %8.3f %8.2f         | %5.1f | %s%s\n",
      config_name(r.config).c_str(), r.units_total, r.client_rate, r.server_rate, r.lease_p50,
      r.lease_p99, r.upload_p50, r.upload_p99, r.upload_max, r.accum_bytes, r.proto_bytes,
      r.server_cpu_ms, r.client_cpu_ms, r.server_cpu_listen_s, r.server_cpu_life_ms,
      100.0 * r.early_fraction, r.problems.empty() ? "yes" : "NO", r.cut_off ? " (cut off)" : "");
  if (label[0]) {
    std::printf("    %s\n", label);
    // One line per run for scripts (tests/load/capacity.sh): key=value, no spaces in values.
    std::printf(
        "    run: tile=%d workers=%d per_call=%u units=%u accepted=%llu merged_per_s=%.1f "
        "lease_p99_ms=%.2f lease_p99_later_ms=%.2f cpu_listen_s=%.4f cpu_run_s=%.4f "
        "cpu_life_ms_per_res=%.4f cpu_run_ms_per_res=%.4f checks=%s cut_off=%d\n",
        r.config.tile, r.config.workers, r.per_call, r.units_total,
        static_cast<unsigned long long>(r.accepted), r.server_rate, r.lease_p99, r.lease_p99_later,
        r.server_cpu_listen_s, r.server_cpu_run_s, r.server_cpu_life_ms, r.server_cpu_ms,
        r.problems.empty() ? "passed" : "FAILED", r.cut_off ? 1 : 0);
  }
  std::fflush(stdout);
}

RunResult median_of(const std::vector<RunResult>& runs) {
  RunResult m = runs.front();
  auto med = [&](double RunResult::*field) {
    std::vector<double> v;
    for (const RunResult& r : runs) v.push_back(r.*field);
    m.*field = median(v);
  };
  for (double RunResult::*f :
       {&RunResult::client_rate, &RunResult::server_rate, &RunResult::lease_p50,
        &RunResult::lease_p99, &RunResult::lease_p99_later, &RunResult::upload_p50, &RunResult::upload_p99,
        &RunResult::upload_max, &RunResult::accum_bytes, &RunResult::proto_bytes,
        &RunResult::server_cpu_ms, &RunResult::client_cpu_ms, &RunResult::early_fraction,
        &RunResult::server_cpu_life_ms, &RunResult::server_cpu_listen_s,
        &RunResult::server_cpu_run_s}) {
    med(f);
  }
  m.cut_off = false;
  m.problems.clear();
  for (const RunResult& r : runs) {
    m.cut_off = m.cut_off || r.cut_off;
    m.problems.insert(m.problems.end(), r.problems.begin(), r.problems.end());
  }
  return m;
}

}  // namespace tessera::bench_merge
