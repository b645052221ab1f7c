#include "worker_registry.h"

#include <cstdio>

#include "store/job_state.h"

namespace tessera::server {
namespace {

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g%%", 100.0 * fraction);
  return text;
}

}  // namespace

std::string health_warning(const WorkerRecord& worker, double report_fraction) {
  if (worker.samples_returned < kMinSamplesToJudge || worker.samples_returned == 0) return {};
  const uint64_t bad = worker.nan_dropped + worker.inf_dropped;
  const double fraction = double(bad) / double(worker.samples_returned);
  if (fraction <= report_fraction) return {};
  return percent(fraction) + " of its samples were NaN/Inf (" + std::to_string(worker.nan_dropped) +
         " NaN, " + std::to_string(worker.inf_dropped) + " Inf; report threshold " +
         percent(report_fraction) + ")";
}

int64_t WorkerRegistry::register_worker(const WorkerRegistration& info, int64_t now) {
  Transaction tx(db_);
  const int64_t id = table_.insert(info, now);
  tx.commit();
  return id;
}

bool WorkerRegistry::touch(int64_t worker_id, int64_t now) {
  Transaction tx(db_);
  const bool found = table_.touch(worker_id, now);
  tx.commit();
  return found;
}

std::optional<WorkerRecord> WorkerRegistry::get(int64_t worker_id) { return table_.get(worker_id); }

std::vector<WorkerRecord> WorkerRegistry::list() { return table_.list(); }

}  // namespace tessera::server
