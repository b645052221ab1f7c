#include "store/job_state.h"

namespace tessera::server {

std::optional<JobState> next_state(JobState from, JobEvent event) {
  switch (from) {
    case JobState::queued:
      switch (event) {
        case JobEvent::start: return JobState::running;
        case JobEvent::finish: return std::nullopt;  // a job finishes only after running
        case JobEvent::fail: return JobState::failed;
        case JobEvent::cancel: return JobState::cancelled;
      }
      break;
    case JobState::running:
      switch (event) {
        case JobEvent::start: return JobState::running;
        case JobEvent::finish: return JobState::done;
        case JobEvent::fail: return JobState::failed;
        case JobEvent::cancel: return JobState::cancelled;
      }
      break;
    case JobState::done:
    case JobState::failed:
    case JobState::cancelled:
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<UnitState> next_state(UnitState from, UnitEvent event) {
  switch (from) {
    case UnitState::queued:
      switch (event) {
        case UnitEvent::lease: return UnitState::leased;
        case UnitEvent::cancel:
        case UnitEvent::skip: return UnitState::cancelled;
        case UnitEvent::accept:
        case UnitEvent::expire:
        case UnitEvent::release: return std::nullopt;
      }
      break;
    case UnitState::leased:
      switch (event) {
        case UnitEvent::accept: return UnitState::done;
        case UnitEvent::expire:
        case UnitEvent::release: return UnitState::queued;
        case UnitEvent::cancel:
        case UnitEvent::skip: return UnitState::cancelled;
        case UnitEvent::lease: return std::nullopt;  // the scheduler hands back the same lease
      }
      break;
    case UnitState::done:
    case UnitState::cancelled:
      return std::nullopt;
  }
  return std::nullopt;
}

bool is_final(JobState state) {
  return state == JobState::done || state == JobState::failed || state == JobState::cancelled;
}

std::string_view to_string(JobState state) {
  switch (state) {
    case JobState::queued: return "queued";
    case JobState::running: return "running";
    case JobState::done: return "done";
    case JobState::failed: return "failed";
    case JobState::cancelled: return "cancelled";
  }
  return "unknown";
}

std::string_view to_string(UnitState state) {
  switch (state) {
    case UnitState::queued: return "queued";
    case UnitState::leased: return "leased";
    case UnitState::done: return "done";
    case UnitState::cancelled: return "cancelled";
  }
  return "unknown";
}

std::string_view to_string(JobEvent event) {
  switch (event) {
    case JobEvent::start: return "start";
    case JobEvent::finish: return "finish";
    case JobEvent::fail: return "fail";
    case JobEvent::cancel: return "cancel";
  }
  return "unknown";
}

std::string_view to_string(UnitEvent event) {
  switch (event) {
    case UnitEvent::lease: return "lease";
    case UnitEvent::accept: return "accept";
    case UnitEvent::expire: return "expire";
    case UnitEvent::release: return "release";
    case UnitEvent::cancel: return "cancel";
    case UnitEvent::skip: return "skip";
  }
  return "unknown";
}

std::optional<JobState> job_state_from_string(std::string_view name) {
  for (JobState s : {JobState::queued, JobState::running, JobState::done, JobState::failed,
                     JobState::cancelled}) {
    if (to_string(s) == name) return s;
  }
  return std::nullopt;
}

std::optional<UnitState> unit_state_from_string(std::string_view name) {
  for (UnitState s : {UnitState::queued, UnitState::leased, UnitState::done, UnitState::cancelled}) {
    if (to_string(s) == name) return s;
  }
  return std::nullopt;
}

}  // namespace tessera::server
