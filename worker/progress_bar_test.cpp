#include "progress_bar.h"

#include <gtest/gtest.h>

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

// stderr redirected to a log: ten plain lines (one per tenth), no '\r' frames.
TEST(ProgressBar, NotATerminalWritesOnePlainLinePerTenth) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProgressBar bar(log, 1000);  // a temporary file is not a terminal
    for (uint64_t done = 1; done <= 1000; ++done) bar.update(done);
    bar.finish(1000);
  }
  const std::string text = contents(log);
  std::fclose(log);
  EXPECT_EQ(text.find('\r'), std::string::npos) << text;
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 10u) << text;
  EXPECT_NE(text.find("progress  10.0%"), std::string::npos) << text;
  EXPECT_NE(text.find("progress 100.0%"), std::string::npos) << text;
}

TEST(ProgressBar, FinishAfterAnEarlyStopEndsWithALine) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProgressBar bar(log, 1000, ProgressBar::Style::lines);
    bar.update(50);   // under a tenth: nothing yet
    bar.finish(50);   // a stopped render still says where it stopped
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
    ProgressBar bar(tty, 100, ProgressBar::Style::redraw);
    bar.update(40);
    bar.finish(100);
  }
  const std::string text = contents(tty);
  std::fclose(tty);
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace tessera
