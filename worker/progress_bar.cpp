#include "progress_bar.h"

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace tessera {

ProgressBar::ProgressBar(std::FILE* stream, uint64_t total_samples, double time_budget_s)
    : ProgressBar(stream, total_samples, time_budget_s,
                  stream != nullptr && isatty(fileno(stream)) != 0 ? Style::redraw
                                                                   : Style::lines) {}

ProgressBar::ProgressBar(std::FILE* stream, uint64_t total_samples, double time_budget_s,
                         Style style, Clock clock)
    : stream_(stream),
      style_(style),
      total_(total_samples == 0 ? 1 : total_samples),
      budget_s_(time_budget_s > 0 ? time_budget_s : 0),
      clock_(or_steady_clock(std::move(clock))),
      start_(clock_()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

double ProgressBar::elapsed_s() const {
  return std::chrono::duration<double>(clock_() - start_).count();
}

double ProgressBar::fraction(uint64_t done, double elapsed) const {
  const double f = budget_s_ > 0 ? elapsed / budget_s_ : double(done) / double(total_);
  return std::clamp(f, 0.0, 1.0);
}

void ProgressBar::update(uint64_t done_samples, uint64_t traced_samples) {
  if (stream_ == nullptr) return;
  if (style_ == Style::lines) {
    // A line per tenth of the work: how many depends on the work alone (for a time job, on the
    // time of the updates), never on when the lines are drawn.
    if (int(fraction(done_samples, elapsed_s()) * 10) > tenths_printed_) {
      print_line(done_samples, traced_samples);
    }
    return;
  }
  const auto now = clock_();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done_samples, traced_samples, false);
}

void ProgressBar::finish(uint64_t done_samples, uint64_t traced_samples) {
  if (stream_ == nullptr) return;
  if (style_ == Style::lines) {
    if (tenths_printed_ < 10) print_line(done_samples, traced_samples);
    return;
  }
  draw(done_samples, traced_samples, true);
  std::fputc('\n', stream_);
}

std::string ProgressBar::elapsed_text(double elapsed) const {
  std::string text = "elapsed " + format_duration(elapsed);
  if (budget_s_ > 0) text += " of " + format_duration(budget_s_);
  return text;
}

void ProgressBar::print_line(uint64_t done, uint64_t traced) {
  const double elapsed = elapsed_s();
  const double f = fraction(done, elapsed);
  tenths_printed_ = int(f * 10);
  const double rate = elapsed > 0 ? double(traced) / elapsed : 0;
  std::fprintf(stream_, "progress %5.1f%%  %ssamples/s  %s\n", 100.0 * f, si_count(rate).c_str(),
               elapsed_text(elapsed).c_str());
  std::fflush(stream_);
}

void ProgressBar::draw(uint64_t done, uint64_t traced, bool final) {
  const double elapsed = elapsed_s();
  const double f = fraction(done, elapsed);
  const int width = 30;
  const int filled = int(f * width);
  std::string bar(size_t(filled), '#');
  bar.resize(size_t(width), '.');
  const double rate = elapsed > 0 ? double(traced) / elapsed : 0;
  std::string eta = "-";
  if (!final && budget_s_ > 0) {
    eta = format_duration(std::max(0.0, budget_s_ - elapsed));
  } else if (!final && rate > 0 && done < total_) {
    eta = format_duration(double(total_ - done) / rate);
  }
  std::fprintf(stream_, "\r[%s] %5.1f%%  %ssamples/s  %s  ETA %s   ", bar.c_str(), f * 100.0,
               si_count(rate).c_str(), elapsed_text(elapsed).c_str(), eta.c_str());
  std::fflush(stream_);
}

std::string si_count(double v) {
  char buf[32];
  if (v >= 1e9) {
    std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
  } else if (v >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
  } else if (v >= 1e3) {
    std::snprintf(buf, sizeof buf, "%.1f k", v / 1e3);
  } else {
    std::snprintf(buf, sizeof buf, "%.0f ", v);
  }
  return buf;
}

std::string format_duration(double s) {
  char buf[32];
  if (s < 60) {
    std::snprintf(buf, sizeof buf, "%.1f s", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof buf, "%d m %02d s", int(s / 60), int(std::fmod(s, 60)));
  } else {
    std::snprintf(buf, sizeof buf, "%d h %02d m", int(s / 3600), int(std::fmod(s, 3600) / 60));
  }
  return buf;
}

}  // namespace tessera
