// The one state machine of job and work-unit status (docs/design.md, "Leases and failures"). Every transition the
// farm makes is decided here, in the two switches of job_state.cpp; the store applies them as
// compare-and-set updates (`UPDATE ... SET state = <to> WHERE ... AND state = <from>`).
//
//   job:   queued --start--> running --finish--> done
//          queued | running --cancel--> cancelled
//          queued | running --fail--> failed
//          (running --start--> running: later leases change nothing)
//   unit:  queued --lease--> leased --accept--> done
//          leased --expire | release--> queued
//          queued | leased --cancel--> cancelled      (its job was cancelled or failed)
//          queued | leased --skip--> cancelled        (its job's stopping rule needs it no more:
//                                                      its tile met the noise target, or the
//                                                      time budget ran out while it was queued)
#pragma once

#include <optional>
#include <string_view>

namespace tessera::server {

enum class JobState { queued, running, done, failed, cancelled };
enum class JobEvent { start, finish, fail, cancel };

enum class UnitState { queued, leased, done, cancelled };
enum class UnitEvent { lease, accept, expire, release, cancel, skip };

/// The state after `event`, or nullopt when the event is not allowed in `from` (the caller
/// answers FAILED_PRECONDITION or drops the request).
std::optional<JobState> next_state(JobState from, JobEvent event);
std::optional<UnitState> next_state(UnitState from, UnitEvent event);

/// True for done, failed and cancelled: nothing changes a finished job.
bool is_final(JobState state);

/// Names as stored in SQLite and printed by the CLI ("queued", "running", ...).
std::string_view to_string(JobState state);
std::string_view to_string(UnitState state);
std::string_view to_string(JobEvent event);
std::string_view to_string(UnitEvent event);

/// Parses a stored name; nullopt when unknown.
std::optional<JobState> job_state_from_string(std::string_view name);
std::optional<UnitState> unit_state_from_string(std::string_view name);

}  // namespace tessera::server
