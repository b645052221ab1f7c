#include "store/job_record.h"

#include <algorithm>

namespace tessera::server {

double JobRecord::progress() const {
  if (options.rule != StopRule::spp) {
    if (state == JobState::done || units_total == 0) return state == JobState::done ? 1.0 : 0.0;
    double settled = double(counters.units_done + counters.units_skipped) / units_total;
    if (options.rule == StopRule::time && options.time_budget_s > 0 && started_unix_ms > 0 &&
        read_unix_ms > started_unix_ms) {
      // A time job is mostly its budget: report the share of it used (it ends soon after).
      settled = std::max(settled, 0.99 * double(read_unix_ms - started_unix_ms) /
                                      (1000.0 * options.time_budget_s));
    }
    return std::min(settled, state == JobState::done ? 1.0 : 0.99);
  }
  const double asked = double(options.width) * double(options.height) * double(options.spp);
  if (asked <= 0) return 0;
  if (units_total > 0 && counters.results_merged == units_total) return 1.0;
  return std::min(1.0, double(counters.samples_merged) / asked);
}

double JobRecord::wall_time_s() const {
  if (started_unix_ms <= 0) return 0;
  const int64_t end = finished_unix_ms > 0 ? finished_unix_ms : read_unix_ms;
  return end > started_unix_ms ? double(end - started_unix_ms) / 1000.0 : 0.0;
}

}  // namespace tessera::server
