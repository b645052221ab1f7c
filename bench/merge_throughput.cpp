// tessera-bench-merge: the server's merge throughput: how many results per second a real
// tessera-server accepts and merges when N simulated workers lease units and upload results as
// fast as it answers.
//
// Per run: a fresh tessera-server child process on 127.0.0.1 (port 0, --port-file) with its own
// temporary SQLite database; one job submitted through JobService (the scene bundle of
// scenes/cornell.json, 256x256, many small units); N threads speaking the worker protocol over
// real gRPC (Register once, then LeaseUnit -> UploadResult until the job ends). Nothing renders:
// every result is an encoded Accumulation precomputed before the clock starts (one per tile
// rectangle — the codec writes the rectangle into the bytes — with plausible noisy float-valued
// sums), so the figure is the server's: gRPC, decode, SQLite transaction, in-order merge,
// re-encode of the tile, the job's output at the end.
//
// After each run the job must be DONE with results_merged == units_done == units_total,
// results_dropped == leases_expired == units_released == 0, and every unit acknowledged exactly
// once on the client side: the benchmark also shows that nothing is lost under load. Any
// violation is printed and makes the exit status 1.
//
//   tessera-bench-merge                                  # tiles 16,32,64 x workers 1,4,16,64
//   tessera-bench-merge --tiles 32 --workers 16 --reps 5 --channel shared
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "merge_bench_report.h"
#include "merge_bench_run.h"
#include "merge_bench_server.h"
#include "merge_bench_util.h"

using namespace tessera::bench_merge;

namespace {

template <typename T>
std::vector<T> parse_list(const std::string& text, const char* flag) {
  std::vector<T> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      const long v = std::stol(item);
      if (v < 1) throw std::out_of_range("");
      values.push_back(T(v));
    } catch (const std::exception&) {
      throw BenchError(std::string(flag) +
                       ": expected positive integers separated by commas (got \"" + text + "\")");
    }
  }
  if (values.empty()) throw BenchError(std::string(flag) + ": empty list");
  return values;
}

fs::path default_server_bin() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path("tessera-server") : self.parent_path() / "tessera-server";
}

/// `reps` runs of one configuration, each printed as it ends; their median.
RunResult run_configuration(const Options& options, const RunConfig& config, int reps, const fs::path& temp,
                            int& run_index) {
  std::vector<RunResult> runs;
  for (int rep = 0; rep < reps; ++rep) {
    RunResult r = run_once(options, config, temp / ("run-" + std::to_string(run_index)), run_index);
    ++run_index;
    char final_ms[32];
    std::snprintf(final_ms, sizeof final_ms, "%.1f", r.final_upload_ms);
    const std::string label = "load " + r.load_before + " -> " + r.load_after +
                              (r.cut_off ? std::string("; cut off after --max-seconds")
                                         : std::string("; last upload (completes the job, writes EXR+PNG) ") +
                                               final_ms + " ms");
    print_row(r, label.c_str());
    for (const std::string& p : r.problems) std::printf("    PROBLEM: %s\n", p.c_str());
    for (size_t i = 0; i < r.server_log.size() && i < 5; ++i) {
      std::printf("    server: %s\n", r.server_log[i].c_str());
    }
    runs.push_back(std::move(r));
  }
  return median_of(runs);
}

/// What the table's columns mean.
void print_legend() {
  std::printf(
      "res/s(client): results accepted / (workers released -> last accepted reply); "
      "merged/s(server): results_merged / (job's started_unix_ms -> finished_unix_ms: first "
      "lease to\n"
      "the last merge; the server stamps finished before writing the output).\n"
      "proto B/res: protobuf payloads of LeaseUnit request+reply and UploadResult "
      "request+reply (no gRPC/HTTP2 framing). early%%: uploads sent before the tile's "
      "previous batch was acknowledged (stored as pending, merged later).\n"
      "srv CPU ms/res: the server's CPU from the clock's start (every worker registered) to the "
      "job's end per accepted result; srv CPU s listen: its CPU at listening (exec, linking, "
      "store, gRPC set-up: a fixed cost of the run);\n"
      "ms/res life: its CPU from exec to the job's end per result (start-up included). The "
      "marginal cost per result is the difference of two job sizes (tests/load/capacity.sh).\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The server's merge throughput: a real tessera-server, N simulated workers over gRPC "
      "uploading precomputed results"};
  Options options;
  options.server_bin = default_server_bin();
  options.scene = fs::path(TESSERA_SOURCE_DIR) / "scenes" / "cornell.json";
  std::string tiles_text = "16,32,64", batches_text = "1", workers_text = "1,4,16,64";
  std::string channel = "own";
  int reps = 1;
  app.add_option("--server-bin", options.server_bin, "tessera-server binary")
      ->capture_default_str();
  app.add_option("--scene", options.scene, "scene file submitted (bundled with what it references)")
      ->capture_default_str();
  app.add_option("--size", options.size, "image width and height, pixels")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  app.add_option("--tiles", tiles_text, "tile sizes, comma-separated")->capture_default_str();
  app.add_option("--batch", batches_text, "batch sizes (spp per unit), comma-separated")
      ->capture_default_str();
  app.add_option("--workers", workers_text, "simulated worker counts, comma-separated")
      ->capture_default_str();
  app.add_option("--channel", channel,
                 "own: one channel (TCP connection) per simulated worker; shared: one for all")
      ->check(CLI::IsMember({"own", "shared"}))
      ->capture_default_str();
  app.add_option("--units", options.units, "units per job (rounded up to whole batches per tile)")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-seconds", options.max_seconds,
                 "bound on each run; a job not finished by then is cut off (workers stop)")
      ->check(CLI::Range(1.0, 600.0))
      ->capture_default_str();
  app.add_option("--wait-ms", options.wait_ms, "LeaseUnit long-poll wait when there is no work")
      ->check(CLI::Range(0u, 5000u))
      ->capture_default_str();
  app.add_option("--lease-seconds", options.lease_seconds, "the server's --lease-seconds")
      ->capture_default_str();
  app.add_option("--per-call", options.per_call,
                 "units leased per LeaseUnit call (max_units) and results per UploadResults call;"
                 " 1: LeaseUnit and UploadResult as workers before batched calls")
      ->check(CLI::Range(1u, 64u))
      ->capture_default_str();
  app.add_option("--reps", reps, "repetitions of each configuration (medians printed)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_flag("--keep", options.keep, "keep the temporary folder (databases, server logs)");
  app.add_option("--trace", options.trace,
                 "PREFIX: write every call's times, the workers' to PREFIX-N.client and the "
                 "server's (TESSERA_CALL_TRACE) to PREFIX-N.server, N the run's index");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!fs::exists(options.server_bin)) {
      throw BenchError("no server binary at " + options.server_bin.string() +
                       " (build tessera-server or pass --server-bin)");
    }
    const auto tiles = parse_list<int>(tiles_text, "--tiles");
    const auto batches = parse_list<uint32_t>(batches_text, "--batch");
    const auto workers = parse_list<int>(workers_text, "--workers");
    TempDir temp(options.keep);
    std::printf(
        "tessera-bench-merge: %dx%d, ~%u units per job, %u unit(s) per call, %d rep(s), server "
        "%s\n",
        options.size, options.size, options.units, options.per_call, reps,
        options.server_bin.c_str());
    std::printf("load average at start: %s (%u CPUs)\n", load_average().c_str(),
                std::thread::hardware_concurrency());
    print_header();

    std::vector<RunResult> medians;
    int run_index = 0;
    for (int tile : tiles) {
      for (uint32_t batch : batches) {
        for (int n : workers) {
          const RunConfig config{tile, batch, n, channel == "shared"};
          medians.push_back(run_configuration(options, config, reps, temp.path(), run_index));
        }
      }
    }
    std::printf("\nmedians over %d rep(s):\n", reps);
    print_header();
    bool ok = true;
    for (const RunResult& m : medians) {
      print_row(m, "");
      ok = ok && m.problems.empty();
    }
    std::printf("load average at end: %s\n", load_average().c_str());
    print_legend();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-merge: %s\n", e.what());
    return 1;
  }
}
