#include "build_text.h"

#include <gtest/gtest.h>

namespace tessera::client {
namespace {

TEST(RendererBuildsText, ALineABuildAndAWarningWhenThereAreSeveral) {
  v1::JobInfo job;
  EXPECT_EQ(renderer_builds_text(job), "");  // nothing merged yet
  job.add_renderer_builds("0.1.0 (commit 0123456789ab, GNU 12.2.0, Embree 3.13.5, glibc 2.36)");
  EXPECT_EQ(renderer_builds_text(job),
            "  builds    0.1.0 (commit 0123456789ab, GNU 12.2.0, Embree 3.13.5, glibc 2.36)\n");
  job.add_renderer_builds("0.1.0 (commit ba9876543210, Clang 14.0.6, Embree 3.13.5, glibc 2.36)");
  const std::string text = renderer_builds_text(job);
  EXPECT_NE(text.find("  builds    0.1.0 (commit ba9876543210, Clang 14.0.6"), std::string::npos) << text;
  EXPECT_NE(text.find("  warning   2 renderer builds rendered this job: its pixels are not one build's bits"),
            std::string::npos)
      << text;
}

TEST(RendererBuildsText, ThePinAndAJobWaitingForItsBuild) {
  v1::JobInfo job;
  job.set_state(v1::JOB_STATE_RUNNING);
  job.set_pinned_build("build A");
  EXPECT_EQ(renderer_builds_text(job), "  pinned    build A\n");
  EXPECT_EQ(state_text(job), "running");
  job.set_waiting_for_build(true);
  EXPECT_EQ(renderer_builds_text(job),
            "  pinned    build A\n  waiting   no online worker of build build A\n");
  EXPECT_EQ(state_text(job), "running (waiting for its build)");
}

TEST(RendererBuildsText, AnAnyBuildJobSaysItsBuildsBesideItsState) {
  v1::JobInfo job;
  job.set_state(v1::JOB_STATE_DONE);
  job.set_any_build(true);
  job.add_renderer_builds("build A");
  job.add_renderer_builds("build B");
  EXPECT_NE(renderer_builds_text(job).find("  pinned    no: submitted with --any-build"),
            std::string::npos);
  EXPECT_EQ(state_text(job), "done (2 renderer builds)");
}

}  // namespace
}  // namespace tessera::client
