// The progress bar of `tessera watch` and `submit --wait`: percent, samples per second and ETA,
// redrawn in place on stderr.
#pragma once

#include <chrono>
#include <cstdio>
#include <deque>
#include <utility>

#include "tessera/v1/job.pb.h"

namespace tessera::client {

class ProgressView {
 public:
  /// `out` nullptr: draws nothing.
  explicit ProgressView(std::FILE* out) : out_(out) {}

  /// Redraws from the job's latest state.
  void update(const v1::JobInfo& job);
  /// Ends the line (after the final update).
  void finish();

 private:
  using clock = std::chrono::steady_clock;
  std::FILE* out_;
  /// (time, pixel samples merged) over the last few seconds: the rate is measured over a
  /// sliding window so that it follows the farm's current speed.
  std::deque<std::pair<clock::time_point, double>> history_;
  bool drawn_ = false;
};

}  // namespace tessera::client
