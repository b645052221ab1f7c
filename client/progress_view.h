// The progress bar of `tessera watch` and `submit --wait`: percent, samples per second and ETA,
// redrawn in place on a terminal; elsewhere (a log, a pipe) one plain line each time the job
// passes another tenth or changes state, never a '\r' frame.
#pragma once

#include <chrono>
#include <cstdio>
#include <deque>
#include <utility>

#include "tessera/v1/job.pb.h"

namespace tessera::client {

class ProgressView {
 public:
  /// `out` nullptr: draws nothing. Redraws in place when `out` is a terminal, plain lines
  /// otherwise.
  explicit ProgressView(std::FILE* out);
  ProgressView(std::FILE* out, bool terminal) : out_(out), terminal_(terminal) {}

  /// Redraws from the job's latest state.
  void update(const v1::JobInfo& job);
  /// Ends the line (after the final update).
  void finish();

 private:
  using clock = std::chrono::steady_clock;
  std::FILE* out_;
  bool terminal_ = false;
  int tenths_printed_ = -1;             ///< plain lines: the last tenth a line was printed for
  v1::JobState state_printed_ = v1::JOB_STATE_UNSPECIFIED;
  /// (time, pixel samples merged) over the last few seconds: the rate is measured over a
  /// sliding window so that it follows the farm's current speed.
  std::deque<std::pair<clock::time_point, double>> history_;
  bool drawn_ = false;
};

}  // namespace tessera::client
