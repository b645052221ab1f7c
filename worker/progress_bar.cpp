#include "progress_bar.h"

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace tessera {

ProgressBar::ProgressBar(std::FILE* stream, uint64_t total_samples)
    : ProgressBar(stream, total_samples,
                  stream != nullptr && isatty(fileno(stream)) != 0 ? Style::redraw
                                                                   : Style::lines) {}

ProgressBar::ProgressBar(std::FILE* stream, uint64_t total_samples, Style style)
    : stream_(stream),
      style_(style),
      total_(total_samples == 0 ? 1 : total_samples),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

void ProgressBar::update(uint64_t done_samples) {
  if (stream_ == nullptr) return;
  if (style_ == Style::lines) {
    // A line per tenth of the work: how many depends on the work alone, never on the clock.
    if (done_samples * 10 / total_ > uint64_t(tenths_printed_)) print_line(done_samples);
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done_samples);
}

void ProgressBar::finish(uint64_t done_samples) {
  if (stream_ == nullptr) return;
  if (style_ == Style::lines) {
    if (tenths_printed_ < 10) print_line(done_samples);
    return;
  }
  draw(done_samples);
  std::fputc('\n', stream_);
}

void ProgressBar::print_line(uint64_t done) {
  tenths_printed_ = int(std::min<uint64_t>(10, done * 10 / total_));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? double(done) / elapsed : 0;
  std::fprintf(stream_, "progress %5.1f%%  %ssamples/s  elapsed %s\n",
               100.0 * double(done) / double(total_), si_count(rate).c_str(),
               format_duration(elapsed).c_str());
  std::fflush(stream_);
}

void ProgressBar::draw(uint64_t done) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = double(done) / double(total_);
  const int width = 30;
  const int filled = int(fraction * width);
  std::string bar(size_t(filled), '#');
  bar.resize(size_t(width), '.');
  const double rate = elapsed > 0 ? double(done) / elapsed : 0;
  const std::string eta =
      rate > 0 && done < total_ ? format_duration(double(total_ - done) / rate) : "-";
  std::fprintf(stream_, "\r[%s] %5.1f%%  %ssamples/s  elapsed %s  ETA %s   ", bar.c_str(),
               fraction * 100.0, si_count(rate).c_str(), format_duration(elapsed).c_str(),
               eta.c_str());
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
