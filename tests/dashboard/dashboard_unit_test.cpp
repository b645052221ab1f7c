// Unit tests of the dashboard's pieces that need no server: the metrics recorder on a fake
// clock and the Prometheus text.
#include <gtest/gtest.h>

#include "dashboard/farm_metrics.h"
#include "dashboard/prometheus_text.h"
#include "fake_clock.h"

namespace tessera::server {
namespace {

TEST(FarmMetrics, RatesOverTheWindowPerWorkerAndJob) {
  testing::FakeClock clock;
  FarmMetrics m(clock);
  clock.advance(20'000);
  m.record_result(/*worker*/ 1, /*job*/ 7, true, 1000, 0.002);
  m.record_result(2, 7, true, 3000, 0.02);
  m.record_result(2, 8, false, 500, 0.3);  // dropped: no samples counted
  clock.advance(2'000);
  // Window of 10 s: 4000 samples / 10 s.
  EXPECT_DOUBLE_EQ(m.farm_samples_per_s(), 400.0);
  EXPECT_DOUBLE_EQ(m.worker_samples_per_s(2), 300.0);
  // A job that started 4 s ago is averaged over those 4 s.
  EXPECT_DOUBLE_EQ(m.job_samples_per_s(7, clock.now_unix_ms() - 4'000), 1000.0);
  EXPECT_DOUBLE_EQ(m.job_samples_per_s(8, 0), 0.0);
  EXPECT_EQ(m.results_accepted(), 2u);
  EXPECT_EQ(m.results_dropped(), 1u);
  clock.advance(FarmMetrics::kRateWindowMs);
  EXPECT_DOUBLE_EQ(m.farm_samples_per_s(), 0.0);  // everything left the window
}

TEST(FarmMetrics, MergeLatencyHistogramIsCumulative) {
  testing::FakeClock clock;
  FarmMetrics m(clock);
  m.record_result(1, 1, true, 1, 0.0005);
  m.record_result(1, 1, true, 1, 0.02);
  m.record_result(1, 1, true, 1, 10.0);
  const FarmMetrics::MergeHistogram h = m.merge_latency();
  EXPECT_EQ(h.count, 3u);
  EXPECT_EQ(h.cumulative.front(), 1u);   // <= 1 ms
  EXPECT_EQ(h.cumulative[4], 2u);        // <= 25 ms
  EXPECT_EQ(h.cumulative.back(), 2u);    // <= 2.5 s: the 10 s one only in +Inf
  EXPECT_NEAR(h.sum_s, 10.0205, 1e-12);
}

TEST(PrometheusText, EveryFamilyHasHelpTypeAndSamples) {
  FarmSnapshotForMetrics s;
  s.totals.jobs_by_state = {{"done", 2}, {"queued", 1}};
  s.totals.units_done = 12;
  s.totals.workers = 3;
  s.workers_online = 2;
  s.merge.count = 4;
  s.merge.cumulative.fill(4);
  const std::string text = prometheus_text(s);
  EXPECT_NE(text.find("# TYPE tessera_jobs gauge\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_jobs{state=\"done\"} 2\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_units_done_total 12\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_workers{state=\"offline\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_merge_latency_seconds_bucket{le=\"0.0025\"} 4\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_merge_latency_seconds_bucket{le=\"+Inf\"} 4\n"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace tessera::server
