#include "dashboard/prometheus_text.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace tessera::server {
namespace {

// The shortest of %.15g / %.17g that reads back as the same double (bucket labels stay "0.0025").
std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class Writer {
 public:
  void family(const std::string& name, const std::string& type, const std::string& help) {
    out_ << "# HELP " << name << ' ' << help << '\n' << "# TYPE " << name << ' ' << type << '\n';
  }
  void sample(const std::string& name, const std::string& labels, const std::string& value) {
    out_ << name;
    if (!labels.empty()) out_ << '{' << labels << '}';
    out_ << ' ' << value << '\n';
  }
  /// A family with one unlabelled sample.
  void single(const std::string& name, const std::string& type, const std::string& help,
              uint64_t value) {
    family(name, type, help);
    sample(name, "", std::to_string(value));
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

}  // namespace

std::string prometheus_text(const FarmSnapshotForMetrics& s) {
  Writer w;
  // Read from the store: left out when a damaged store cannot answer (store_readable).
  if (s.store_readable) {
    w.family("tessera_jobs", "gauge", "Jobs in the store by state.");
    for (const auto& [state, count] : s.totals.jobs_by_state) {
      w.sample("tessera_jobs", "state=\"" + state + "\"", std::to_string(count));
    }
    w.single("tessera_units_leased", "gauge",
             "Work units leased to workers right now.",
             s.totals.units_leased_now);
    w.single("tessera_units_done_total", "counter",
             "Work units whose result was accepted, over every job in the store.",
             s.totals.units_done);
    w.single("tessera_units_expired_total", "counter",
             "Leases that expired or were revoked at a restart (units rendered again), all jobs.",
             s.totals.leases_expired);
    w.single("tessera_results_dropped_total", "counter",
             "Results dropped for a stale or duplicate lease, over every job in the store.",
             s.totals.results_dropped);
    w.single("tessera_samples_merged_total", "counter",
             "Pixel samples merged, over every job in the store.",
             s.totals.samples_merged);
  }
  w.family("tessera_results_received_total", "counter",
           "Results answered by this server process, by outcome (accepted or dropped).");
  w.sample("tessera_results_received_total", "outcome=\"accepted\"",
           std::to_string(s.results_accepted));
  w.sample("tessera_results_received_total", "outcome=\"dropped\"",
           std::to_string(s.results_dropped_session));
  w.family("tessera_samples_per_second", "gauge",
           "Pixel samples accepted per second over the last 10 seconds.");
  w.sample("tessera_samples_per_second", "", number(s.samples_per_s));
  if (s.store_readable) {
    w.family("tessera_workers", "gauge", "Registered workers, online (seen within 3 leases) or not.");
    w.sample("tessera_workers", "state=\"online\"", std::to_string(s.workers_online));
    w.sample("tessera_workers", "state=\"offline\"",
             std::to_string(s.totals.workers - s.workers_online));
    // docs/reliability.md, "Spot checks": alert on tessera_workers_quarantined > 0.
    w.single("tessera_workers_quarantined", "gauge",
             "Worker names quarantined (a spot check found their result wrong).",
             s.workers_quarantined);
  }
  w.family("tessera_spot_checks_total", "counter",
           "Spot checks since the server started: units whose two results agreed (checked), "
           "results that disagreed with the verdict (mismatch), results merged without the "
           "check they were due (unverified).");
  w.sample("tessera_spot_checks_total", "outcome=\"checked\"", std::to_string(s.checks.checked));
  w.sample("tessera_spot_checks_total", "outcome=\"mismatch\"",
           std::to_string(s.checks.mismatches));
  w.sample("tessera_spot_checks_total", "outcome=\"unverified\"",
           std::to_string(s.checks.unverified));
  // The store (docs/reliability.md, "A consistent database after any crash"): alert on
  // tessera_store_damaged == 1; the server then hands out no more work.
  w.single("tessera_store_damaged", "gauge",
           "1 when the background check of the database found damage (leasing stopped), else 0.",
           s.store.damaged() ? 1 : 0);
  w.single("tessera_store_check_running", "gauge",
           "1 while the database is checked (PRAGMA quick_check) after an unclean stop, else 0.",
           s.store.checking() ? 1 : 0);
  // Alert on tessera_store_full == 1: uploads and submissions fail until there is space
  // (docs/reliability.md, "A full disk").
  w.single("tessera_store_full", "gauge",
           "1 while the database cannot write for lack of space (SQLITE_FULL), else 0.",
           s.store.full() ? 1 : 0);
  w.family("tessera_merge_latency_seconds", "histogram",
           "Time from receiving a result to its commit (decode, lock, compare-and-set, merge).");
  for (size_t i = 0; i < FarmMetrics::kMergeBuckets.size(); ++i) {
    w.sample("tessera_merge_latency_seconds_bucket",
             "le=\"" + number(FarmMetrics::kMergeBuckets[i]) + "\"",
             std::to_string(s.merge.cumulative[i]));
  }
  w.sample("tessera_merge_latency_seconds_bucket", "le=\"+Inf\"", std::to_string(s.merge.count));
  w.sample("tessera_merge_latency_seconds_sum", "", number(s.merge.sum_s));
  w.sample("tessera_merge_latency_seconds_count", "", std::to_string(s.merge.count));
  if (s.submit_memory) {
    // docs/farm.md, "The server's memory".
    const SubmitBudget::Counters& m = *s.submit_memory;
    w.single("tessera_submit_memory_budget_bytes", "gauge",
             "Memory for checking submitted bundles (--submit-memory-mb).", m.capacity_bytes);
    w.single("tessera_submit_memory_reserved_bytes", "gauge",
             "Submit check memory reserved now.", m.reserved_bytes);
    w.single("tessera_submit_memory_peak_bytes", "gauge",
             "The most submit check memory reserved at once since the server started.",
             m.peak_reserved_bytes);
    w.family("tessera_submits_checked_total", "counter",
             "Submits by what the memory budget did with them: admitted at once, admitted after "
             "waiting, refused as larger than the budget, refused after waiting.");
    w.sample("tessera_submits_checked_total", "budget=\"admitted\"",
             std::to_string(m.admitted - m.waited));
    w.sample("tessera_submits_checked_total", "budget=\"waited\"", std::to_string(m.waited));
    w.sample("tessera_submits_checked_total", "budget=\"too_large\"",
             std::to_string(m.refused_too_large));
    w.sample("tessera_submits_checked_total", "budget=\"busy\"",
             std::to_string(m.refused_busy));
  }
  return w.str();
}

}  // namespace tessera::server
