#include "store/job_state.h"

#include <gtest/gtest.h>

namespace tessera::server {
namespace {

constexpr JobState kJobStates[] = {JobState::queued, JobState::running, JobState::done,
                                   JobState::failed, JobState::cancelled};
constexpr JobEvent kJobEvents[] = {JobEvent::start, JobEvent::finish, JobEvent::fail,
                                   JobEvent::cancel};
constexpr UnitState kUnitStates[] = {UnitState::queued, UnitState::leased, UnitState::done,
                                     UnitState::cancelled};
constexpr UnitEvent kUnitEvents[] = {UnitEvent::lease, UnitEvent::accept, UnitEvent::expire,
                                     UnitEvent::release, UnitEvent::cancel,
                                     UnitEvent::skip};

TEST(JobStateMachine, LifecycleOfAJob) {
  EXPECT_EQ(next_state(JobState::queued, JobEvent::start), JobState::running);
  EXPECT_EQ(next_state(JobState::running, JobEvent::start), JobState::running);
  EXPECT_EQ(next_state(JobState::running, JobEvent::finish), JobState::done);
  EXPECT_EQ(next_state(JobState::queued, JobEvent::cancel), JobState::cancelled);
  EXPECT_EQ(next_state(JobState::running, JobEvent::cancel), JobState::cancelled);
  EXPECT_EQ(next_state(JobState::queued, JobEvent::fail), JobState::failed);
  EXPECT_EQ(next_state(JobState::running, JobEvent::fail), JobState::failed);
  // A job cannot finish without having run.
  EXPECT_EQ(next_state(JobState::queued, JobEvent::finish), std::nullopt);
}

TEST(JobStateMachine, FinalStatesAcceptNoEvent) {
  for (JobState s : kJobStates) {
    EXPECT_EQ(is_final(s), s == JobState::done || s == JobState::failed || s == JobState::cancelled);
    if (!is_final(s)) continue;
    for (JobEvent e : kJobEvents) {
      EXPECT_EQ(next_state(s, e), std::nullopt) << to_string(s) << " + " << to_string(e);
    }
  }
}

TEST(UnitStateMachine, EveryTransition) {
  // The complete table: (from, event) -> to, or nothing.
  for (UnitState s : kUnitStates) {
    for (UnitEvent e : kUnitEvents) {
      std::optional<UnitState> expected;
      if (s == UnitState::queued && e == UnitEvent::lease) expected = UnitState::leased;
      if (s == UnitState::queued && e == UnitEvent::cancel) expected = UnitState::cancelled;
      if (s == UnitState::leased && e == UnitEvent::accept) expected = UnitState::done;
      if (s == UnitState::leased && (e == UnitEvent::expire || e == UnitEvent::release)) {
        expected = UnitState::queued;
      }
      if (s == UnitState::leased && e == UnitEvent::cancel) expected = UnitState::cancelled;
      // The stopping rule's skip: a unit no longer needed, whether queued or leased.
      if ((s == UnitState::queued || s == UnitState::leased) && e == UnitEvent::skip) {
        expected = UnitState::cancelled;
      }
      EXPECT_EQ(next_state(s, e), expected) << to_string(s) << " + " << to_string(e);
    }
  }
}

TEST(StateNames, RoundTrip) {
  for (JobState s : kJobStates) EXPECT_EQ(job_state_from_string(to_string(s)), s);
  for (UnitState s : kUnitStates) EXPECT_EQ(unit_state_from_string(to_string(s)), s);
  EXPECT_EQ(job_state_from_string("finished"), std::nullopt);
  EXPECT_EQ(unit_state_from_string(""), std::nullopt);
}

}  // namespace
}  // namespace tessera::server
