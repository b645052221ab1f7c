#include "progress_bar.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace tessera {
namespace {

std::string contents(std::FILE* f) {
  std::rewind(f);
  std::string text;
  char buf[256];
  while (size_t n = std::fread(buf, 1, sizeof buf, f)) text.append(buf, n);
  return text;
}

size_t line_count(const std::string& text) {
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

/// A clock that stands still until the test moves it.
struct BarClock {
  std::chrono::steady_clock::time_point now{};
  ProgressBar::Clock clock() {
    return [this] { return now; };
  }
  void set_seconds(double s) {
    now = std::chrono::steady_clock::time_point(std::chrono::nanoseconds(int64_t(s * 1e9)));
  }
};

// stderr redirected to a log: ten plain lines (one per tenth), no '\r' frames.
TEST(ProgressBar, NotATerminalWritesOnePlainLinePerTenth) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProgressBar bar(log, 1000);  // a temporary file is not a terminal
    for (uint64_t done = 1; done <= 1000; ++done) bar.update(done, done);
    bar.finish(1000, 1000);
  }
  const std::string text = contents(log);
  std::fclose(log);
  EXPECT_EQ(text.find('\r'), std::string::npos) << text;
  EXPECT_EQ(line_count(text), 10u) << text;
  EXPECT_NE(text.find("progress  10.0%"), std::string::npos) << text;
  EXPECT_NE(text.find("progress 100.0%"), std::string::npos) << text;
}

TEST(ProgressBar, FinishAfterAnEarlyStopEndsWithALine) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProgressBar bar(log, 1000, 0, ProgressBar::Style::lines);
    bar.update(50, 50);   // under a tenth: nothing yet
    bar.finish(50, 50);   // a stopped render still says where it stopped
  }
  const std::string text = contents(log);
  std::fclose(log);
  EXPECT_EQ(text, text.substr(0, text.find('\n') + 1));
  EXPECT_NE(text.find("progress   5.0%"), std::string::npos) << text;
}

TEST(ProgressBar, TerminalStyleRedrawsInPlace) {
  std::FILE* tty = std::tmpfile();
  ASSERT_NE(tty, nullptr);
  {
    ProgressBar bar(tty, 100, 0, ProgressBar::Style::redraw);
    bar.update(40, 40);
    bar.finish(100, 100);
  }
  const std::string text = contents(tty);
  std::fclose(tty);
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(text.back(), '\n');
}

// An spp job's ETA is the samples left at the rate so far; a noise job stopped early shows
// the samples it has, and no ETA for the cap it did not need.
TEST(ProgressBar, SampleJobEtaFollowsTheRateAndFinishHasNone) {
  std::FILE* tty = std::tmpfile();
  ASSERT_NE(tty, nullptr);
  BarClock clock;
  {
    ProgressBar bar(tty, 20000, 0, ProgressBar::Style::redraw, clock.clock());
    clock.set_seconds(2);
    bar.update(4000, 4000);  // 2 ksamples/s: 16000 left, 8 s
    clock.set_seconds(3);
    bar.finish(6000, 6000);
  }
  const std::string text = contents(tty);
  std::fclose(tty);
  const std::string first = text.substr(0, text.find('\r', 1));
  const std::string last = text.substr(text.rfind('\r'));
  EXPECT_NE(first.find(" 20.0%  2.0 ksamples/s  elapsed 2.0 s  ETA 8.0 s"), std::string::npos)
      << text;
  EXPECT_NE(last.find(" 30.0%  2.0 ksamples/s  elapsed 3.0 s  ETA -"), std::string::npos) << text;
}

// A time job's bar follows its budget, not its cap: the percent is the budget elapsed, the ETA
// the rest of it; the rate is what was traced (a batch the budget cut included), per second.
TEST(ProgressBar, TimeJobFollowsTheBudgetAndCountsWhatWasTraced) {
  std::FILE* tty = std::tmpfile();
  ASSERT_NE(tty, nullptr);
  BarClock clock;
  {
    // A 2-second job capped at 100000 spp of 64 x 64 pixels.
    ProgressBar bar(tty, uint64_t(64) * 64 * 100000, 2.0, ProgressBar::Style::redraw,
                    clock.clock());
    clock.set_seconds(0.5);
    bar.update(100000, 100000);
    clock.set_seconds(2.0);
    bar.finish(300000, 400000);  // 300 k in the image, 100 k more traced by a cut batch
  }
  const std::string text = contents(tty);
  std::fclose(tty);
  const std::string first = text.substr(0, text.find('\r', 1));
  const std::string last = text.substr(text.rfind('\r'));
  EXPECT_NE(first.find(" 25.0%  200.0 ksamples/s  elapsed 0.5 s of 2.0 s  ETA 1.5 s"),
            std::string::npos)
      << text;
  EXPECT_NE(last.find("100.0%  200.0 ksamples/s  elapsed 2.0 s of 2.0 s  ETA -"),
            std::string::npos)
      << text;
}

// In a log, a time job prints a line per tenth of its budget, as the updates pass them: ten for
// updates every 0.3 s of a 10 s budget, the last from finish().
TEST(ProgressBar, TimeJobInALogWritesALinePerTenthOfTheBudget) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  BarClock clock;
  {
    ProgressBar bar(log, uint64_t(1) << 40, 10.0, ProgressBar::Style::lines, clock.clock());
    for (int k = 1; k * 0.3 < 10.0; ++k) {
      clock.set_seconds(k * 0.3);
      bar.update(uint64_t(k) * 600, uint64_t(k) * 600);
    }
    clock.set_seconds(10.2);
    bar.finish(20400, 20400);
  }
  const std::string text = contents(log);
  std::fclose(log);
  EXPECT_EQ(line_count(text), 10u) << text;
  EXPECT_NE(text.find("progress  12.0%  2.0 ksamples/s  elapsed 1.2 s of 10.0 s\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("progress 100.0%  2.0 ksamples/s  elapsed 10.2 s of 10.0 s\n"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace tessera
