// tessera-bench-merge (merge_throughput.cpp): its table, one row per run or per configuration.
#pragma once

#include <string>
#include <vector>

#include "merge_bench_run.h"

namespace tessera::bench_merge {

std::string config_name(const RunConfig& c);

void print_header();

void print_row(const RunResult& r, const char* label);

/// The median of each figure over repetitions of one configuration.
RunResult median_of(const std::vector<RunResult>& runs);

}  // namespace tessera::bench_merge
