#include "json_view.h"

#include <cstdio>

#include "job/stopping_rule.h"
#include "job_client.h"
#include "wire/job_json.h"
#include "wire/job_options_wire.h"

namespace tessera::client {

std::string rule_text(const v1::ResolvedJobOptions& o) {
  char buf[128];
  switch (o.stop_rule()) {
    case v1::STOP_RULE_TIME:
      std::snprintf(buf, sizeof buf, "time %g s (max %u spp)", o.time_budget_s(), o.spp());
      return buf;
    case v1::STOP_RULE_NOISE:
      std::snprintf(buf, sizeof buf, "noise %g (max %u spp)", o.noise_target(), o.spp());
      return buf;
    default: return "spp " + std::to_string(o.spp());
  }
}

std::string reason_name(v1::StopReason reason) {
  return std::string(to_string(wire::stop_reason_from_proto(reason)));
}

nlohmann::json to_json(const v1::JobInfo& job) { return wire::job_json(job); }

namespace {

/// A quarantined worker's {job, tile, batch, time_unix_ms, reason, finished_jobs}; else null.
nlohmann::json quarantine_json(const v1::WorkerInfo& w) {
  if (!w.has_quarantine()) return nullptr;
  const v1::WorkerQuarantine& q = w.quarantine();
  return {{"job", q.job_id()},
          {"tile", q.tile()},
          {"batch", q.batch()},
          {"time_unix_ms", q.time_unix_ms()},
          {"reason", q.reason()},
          {"finished_jobs",
           std::vector<uint64_t>(q.finished_jobs().begin(), q.finished_jobs().end())}};
}

}  // namespace

nlohmann::json to_json(const v1::WorkerInfo& w) {
  return {
      {"id", w.id()},
      {"name", w.name()},
      {"threads", w.threads()},
      {"isa", w.isa()},
      {"build", w.build()},
      {"online", w.online()},
      {"last_seen_unix_ms", w.last_seen_unix_ms()},
      // An idle worker renders no unit: its job, tile and batch are null, not job 0's tile 0.
      {"job_id", w.job_id() == 0 ? nlohmann::json(nullptr) : nlohmann::json(w.job_id())},
      {"tile", w.job_id() == 0 ? nlohmann::json(nullptr) : nlohmann::json(w.tile())},
      {"batch", w.job_id() == 0 ? nlohmann::json(nullptr) : nlohmann::json(w.batch())},
      {"units_held", w.units_held()},
      {"units_done", w.units_done()},
      {"units_lost", w.units_lost()},
      {"samples_returned", w.samples_returned()},
      {"nan_dropped", w.nan_dropped()},
      {"inf_dropped", w.inf_dropped()},
      {"health_warning", w.health_warning()},
      {"state", w.state().empty() ? (w.online() ? "online" : "offline") : w.state()},
      {"quarantine", quarantine_json(w)},
      {"checks", w.checks()},
      {"mismatches", w.mismatches()},
  };
}

}  // namespace tessera::client
