// tessera-bench-merge (merge_throughput.cpp): its error, clocks, CPU and load readings and
// percentiles.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::bench_merge {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A failed benchmark step (server would not start, an RPC failed): what() is one line.
class BenchError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

double seconds_between(Clock::time_point t0, Clock::time_point t1);

double ms_between(Clock::time_point t0, Clock::time_point t1);

std::string load_average();

/// User + system CPU seconds of process `pid` (from /proc/PID/stat), or of this process when
/// pid is 0.
double cpu_seconds(pid_t pid);

/// Nearest-rank percentile of `values` (sorted in place); 0 when empty.
double percentile(std::vector<double>& values, double p);

double median(std::vector<double> values);

}  // namespace tessera::bench_merge
