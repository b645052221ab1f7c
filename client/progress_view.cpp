#include "progress_view.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "job_client.h"

namespace tessera::client {
namespace {

std::string si(double v) {
  const char* units[] = {"", "k", "M", "G", "T"};
  int u = 0;
  while (std::abs(v) >= 1000 && u < 4) {
    v /= 1000;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f%s", v, units[u]);
  return buf;
}

std::string duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = long(std::lround(seconds));
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%02ld:%02ld", s / 60, s % 60);
  }
  return buf;
}

}  // namespace

ProgressView::ProgressView(std::FILE* out)
    : ProgressView(out, out != nullptr && isatty(fileno(out)) != 0) {}

void ProgressView::update(const v1::JobInfo& job) {
  if (!out_) return;
  const auto& o = job.options();
  // Samples merged, as the server counts them: exact for every stopping rule.
  const double done = double(job.counters().samples_merged());
  const auto now = clock::now();
  history_.emplace_back(now, done);
  while (history_.size() > 2 && now - history_.front().first > std::chrono::seconds(10)) {
    history_.pop_front();
  }
  double rate = 0;
  if (history_.size() >= 2) {
    const double dt =
        std::chrono::duration<double>(history_.back().first - history_.front().first).count();
    if (dt > 0) rate = (history_.back().second - history_.front().second) / dt;
  }
  constexpr int kWidth = 30;
  const int filled = int(job.progress() * kWidth);
  std::string bar(size_t(filled), '#');
  bar.resize(kWidth, '.');
  // ETA: the remaining samples of an spp job, the rest of a time job's budget; a noise job's end
  // is not known in advance (its bar counts units settled, an upper bound of the work left).
  double eta = NAN;
  std::string extra;
  if (o.stop_rule() == v1::STOP_RULE_TIME) {
    eta = std::max(0.0, o.time_budget_s() - job.wall_time_s());
  } else if (o.stop_rule() == v1::STOP_RULE_NOISE) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "tiles %u/%u  ", job.reached().tiles_finished(),
                  (o.width() + o.tile_size() - 1) / o.tile_size() *
                      ((o.height() + o.tile_size() - 1) / o.tile_size()));
    extra = buf;
  } else {
    const double total = double(o.width()) * double(o.height()) * double(o.spp());
    if (rate > 0) eta = (total - done) / rate;
  }
  const std::string eta_text = is_final(job.state()) ? "00:00" : duration(eta);
  if (!terminal_) {
    // A line per tenth of the job or change of state: how many depends on the job, not the clock.
    const int tenths = int(std::floor(std::clamp(job.progress(), 0.0, 1.0) * 10.0));
    if (tenths <= tenths_printed_ && job.state() == state_printed_) return;
    tenths_printed_ = tenths;
    state_printed_ = job.state();
    std::fprintf(out_, "job %llu %s %5.1f%%  %s%s samples/s  ETA %s\n",
                 static_cast<unsigned long long>(job.id()), state_name(job.state()).c_str(),
                 100.0 * job.progress(), extra.c_str(), si(rate).c_str(), eta_text.c_str());
    std::fflush(out_);
    return;
  }
  std::fprintf(out_, "\rjob %llu %-9s [%s] %5.1f%%  %s%s samples/s  ETA %s  ",
               static_cast<unsigned long long>(job.id()), state_name(job.state()).c_str(),
               bar.c_str(), 100.0 * job.progress(), extra.c_str(), si(rate).c_str(),
               eta_text.c_str());
  std::fflush(out_);
  drawn_ = true;
}

void ProgressView::finish() {
  if (out_ && terminal_ && drawn_) std::fputc('\n', out_);
  drawn_ = false;
}

}  // namespace tessera::client
