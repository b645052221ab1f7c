// /metrics in the Prometheus text exposition format (version 0.0.4): store totals, worker
// counts and the FarmMetrics recorder, every family with HELP and TYPE.
#pragma once

#include <optional>
#include <string>

#include "coordinator.h"
#include "dashboard/farm_metrics.h"
#include "dashboard/store_status.h"

namespace tessera::server {

struct FarmSnapshotForMetrics {
  FarmTotals totals;
  uint64_t workers_online = 0;
  CheckCounts checks;                ///< spot checks since the server started
  uint64_t workers_quarantined = 0;  ///< worker names quarantined now
  double samples_per_s = 0;
  uint64_t results_accepted = 0;          ///< since the server started
  uint64_t results_dropped_session = 0;   ///< since the server started
  FarmMetrics::MergeHistogram merge;
  StoreStatus store;  ///< tessera_store_damaged, tessera_store_check_running, tessera_store_full
  /// False when the store is damaged where `totals` and the worker counts are read: their
  /// families are left out (the store's gauges and this process's counters remain).
  bool store_readable = true;
  /// The submit checks' memory budget (--submit-memory-mb), when the server has one.
  std::optional<SubmitBudget::Counters> submit_memory;
};

std::string prometheus_text(const FarmSnapshotForMetrics& s);

}  // namespace tessera::server
