#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tessera {

/// A one-line progress bar on a terminal: percent, samples/s, elapsed and ETA. Draws nothing
/// when `stream` is not a terminal. Not thread-safe: call update() from one thread.
class ProgressBar {
 public:
  ProgressBar(std::FILE* stream, uint64_t total_samples);
  /// Redraws (at most ten times a second) with `done_samples` of the total finished.
  void update(uint64_t done_samples);
  /// Draws the final state and ends the line.
  void finish(uint64_t done_samples);

 private:
  void draw(uint64_t done_samples);

  std::FILE* stream_;
  bool enabled_;
  uint64_t total_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

/// "1.5 M", "320 k": a count with an SI prefix.
std::string si_count(double value);
/// "1 m 05 s", "3.2 s".
std::string format_duration(double seconds);

}  // namespace tessera
