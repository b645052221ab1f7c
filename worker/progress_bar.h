#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "steady_clock_source.h"

namespace tessera {

/// Progress of a local render: percent, samples/s, elapsed and ETA. On a terminal one line
/// redrawn in place ('\r'); anywhere else (a log file, a pipe) a plain line each time another
/// tenth of the work is done, so that logs get ten short lines instead of one huge one. Draws
/// nothing when `stream` is nullptr. Not thread-safe: call update() from one thread.
///
/// A `time` job's work is its budget, as in `tessera watch` (client/progress_view.cpp): the
/// percent is the share of the budget elapsed and the ETA the rest of it. Any other job's work
/// is its samples: the percent is the samples done of the total, the ETA the rest at the rate
/// so far. The rate is the samples traced per second of elapsed time.
class ProgressBar {
 public:
  enum class Style { redraw, lines };
  /// The bar's time; empty: std::chrono::steady_clock. Tests inject a fake one.
  using Clock = SteadyClockSource;
  /// `total_samples`: the job's pixel samples (at its cap for a `noise` or `time` job);
  /// `time_budget_s` > 0: a `time` job's budget, which the bar then follows. Redraws when
  /// `stream` is a terminal, plain lines otherwise.
  ProgressBar(std::FILE* stream, uint64_t total_samples, double time_budget_s = 0);
  ProgressBar(std::FILE* stream, uint64_t total_samples, double time_budget_s, Style style,
              Clock clock = {});
  /// Redraws (at most ten times a second) with `done_samples` in the image so far and
  /// `traced_samples` traced, the rate's count (a render the time budget cut was traced but is
  /// not in the image).
  void update(uint64_t done_samples, uint64_t traced_samples);
  /// Draws the final state, with no ETA, and ends the line: `done_samples` the samples the
  /// image holds (not the job's total when it stopped early), `traced_samples` as update().
  void finish(uint64_t done_samples, uint64_t traced_samples);

 private:
  double elapsed_s() const;
  /// The share of the work done: of the budget (a time job) or of the samples, in [0, 1].
  double fraction(uint64_t done_samples, double elapsed) const;
  void draw(uint64_t done_samples, uint64_t traced_samples, bool final);
  void print_line(uint64_t done_samples, uint64_t traced_samples);
  std::string elapsed_text(double elapsed) const;

  std::FILE* stream_;
  Style style_;
  int tenths_printed_ = 0;  ///< Style::lines: the last tenth of the work a line was printed for
  uint64_t total_;
  double budget_s_;  ///< > 0: a time job
  Clock clock_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

/// "1.5 M", "320 k": a count with an SI prefix.
std::string si_count(double value);
/// "1 m 05 s", "3.2 s".
std::string format_duration(double seconds);

}  // namespace tessera
