#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tessera {

/// Progress of a local render: percent, samples/s, elapsed and ETA. On a terminal one line
/// redrawn in place ('\r'); anywhere else (a log file, a pipe) a plain line each time another
/// tenth of the work is done, so that logs get ten short lines instead of one huge one. Draws
/// nothing when `stream` is nullptr. Not thread-safe: call update() from one thread.
class ProgressBar {
 public:
  enum class Style { redraw, lines };
  /// Redraws when `stream` is a terminal, plain lines otherwise.
  ProgressBar(std::FILE* stream, uint64_t total_samples);
  ProgressBar(std::FILE* stream, uint64_t total_samples, Style style);
  /// Redraws (at most ten times a second) with `done_samples` of the total finished.
  void update(uint64_t done_samples);
  /// Draws the final state and ends the line.
  void finish(uint64_t done_samples);

 private:
  void draw(uint64_t done_samples);
  void print_line(uint64_t done_samples);

  std::FILE* stream_;
  Style style_;
  int tenths_printed_ = 0;  ///< Style::lines: the last tenth of the work a line was printed for
  uint64_t total_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

/// "1.5 M", "320 k": a count with an SI prefix.
std::string si_count(double value);
/// "1 m 05 s", "3.2 s".
std::string format_duration(double seconds);

}  // namespace tessera
