#include "progress_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace tessera::client {
namespace {

std::string contents(std::FILE* f) {
  std::rewind(f);
  std::string text;
  char buf[256];
  while (size_t n = std::fread(buf, 1, sizeof buf, f)) text.append(buf, n);
  return text;
}

v1::JobInfo job_at(double progress, v1::JobState state) {
  v1::JobInfo job;
  job.set_id(3);
  job.set_state(state);
  job.set_progress(progress);
  job.mutable_options()->set_width(16);
  job.mutable_options()->set_height(16);
  job.mutable_options()->set_spp(100);
  job.mutable_options()->set_tile_size(8);
  job.mutable_options()->set_stop_rule(v1::STOP_RULE_SPP);
  job.mutable_counters()->set_samples_merged(uint64_t(progress * 16 * 16 * 100));
  return job;
}

// `tessera submit --wait 2>log`: a log that is no terminal gets plain lines, not a line of
// '\r' frames per update.
TEST(ProgressView, NotATerminalWritesPlainLinesPerTenthAndState) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProgressView view(log);  // a temporary file is not a terminal
    view.update(job_at(0.0, v1::JOB_STATE_QUEUED));
    view.update(job_at(0.0, v1::JOB_STATE_QUEUED));    // nothing new: no line
    view.update(job_at(0.0, v1::JOB_STATE_RUNNING));   // a new state: a line
    for (int i = 1; i <= 200; ++i) view.update(job_at(i / 200.0, v1::JOB_STATE_RUNNING));
    view.update(job_at(1.0, v1::JOB_STATE_DONE));
    view.finish();
  }
  const std::string text = contents(log);
  std::fclose(log);
  EXPECT_EQ(text.find('\r'), std::string::npos) << text;
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 2u + 10u + 1u) << text;  // queued, running 0 %, each tenth, done
  EXPECT_NE(text.find("job 3 running  50.0%"), std::string::npos) << text;
  EXPECT_NE(text.find("job 3 done 100.0%"), std::string::npos) << text;
}

TEST(ProgressView, ATerminalIsRedrawnInPlace) {
  std::FILE* tty = std::tmpfile();
  ASSERT_NE(tty, nullptr);
  {
    ProgressView view(tty, /*terminal=*/true);
    view.update(job_at(0.5, v1::JOB_STATE_RUNNING));
    view.update(job_at(1.0, v1::JOB_STATE_DONE));
    view.finish();
  }
  const std::string text = contents(tty);
  std::fclose(tty);
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
}

}  // namespace
}  // namespace tessera::client
