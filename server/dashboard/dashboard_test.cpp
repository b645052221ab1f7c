// Unit tests of the dashboard's pieces that need no server: the metrics recorder on a fake
// clock, the Prometheus text, and the store's status (JSON and gauges; a coordinator on a
// damaged store).
#include <gtest/gtest.h>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "coordinator.h"
#include "damaged_store.h"
#include "dashboard/farm_metrics.h"
#include "dashboard/prometheus_text.h"
#include "dashboard/store_status.h"
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
  s.checks = {5, 1, 2};
  s.workers_quarantined = 1;
  s.merge.count = 4;
  s.merge.cumulative.fill(4);
  const std::string text = prometheus_text(s);
  EXPECT_NE(text.find("# TYPE tessera_jobs gauge\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_jobs{state=\"done\"} 2\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_units_done_total 12\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_workers{state=\"offline\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_workers_quarantined 1\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_spot_checks_total{outcome=\"checked\"} 5\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_spot_checks_total{outcome=\"mismatch\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_spot_checks_total{outcome=\"unverified\"} 2\n"),
            std::string::npos);
  EXPECT_NE(text.find("tessera_merge_latency_seconds_bucket{le=\"0.0025\"} 4\n"), std::string::npos);
  EXPECT_NE(text.find("tessera_merge_latency_seconds_bucket{le=\"+Inf\"} 4\n"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
  // A healthy store, no check running.
  EXPECT_NE(text.find("# TYPE tessera_store_damaged gauge\ntessera_store_damaged 0\n"),
            std::string::npos);
  EXPECT_NE(text.find("# TYPE tessera_store_check_running gauge\ntessera_store_check_running 0\n"),
            std::string::npos);
  EXPECT_NE(text.find("# TYPE tessera_store_full gauge\ntessera_store_full 0\n"),
            std::string::npos);
}

// The three states the page shows a banner for (or none), in /api/store's JSON and the gauges.
TEST(StoreStatus, CheckingAndDamagedReadTheSameInTheJsonAndTheGauges) {
  using nlohmann::json;
  StoreStatus none;
  EXPECT_EQ(store_json(none), (json{{"state", "ok"}, {"check", "none"}, {"check_progress", nullptr},
                                    {"damage", ""}, {"leasing", true}, {"write_error", ""}}));

  StoreStatus checking;
  checking.check = "checking";
  checking.check_progress = 0.25;
  EXPECT_EQ(store_json(checking)["state"], "checking");
  EXPECT_EQ(store_json(checking)["check_progress"], 0.25);
  FarmSnapshotForMetrics s;
  s.store = checking;
  std::string text = prometheus_text(s);
  EXPECT_NE(text.find("tessera_store_check_running 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tessera_store_damaged 0\n"), std::string::npos) << text;

  StoreStatus damaged;
  damaged.check = "damaged";
  damaged.check_progress = 0.9;
  damaged.damage = "database x.db is damaged (PRAGMA quick_check: ...)";
  damaged.leasing = false;
  const json j = store_json(damaged);
  EXPECT_EQ(j["state"], "damaged");
  EXPECT_EQ(j["damage"], damaged.damage);
  EXPECT_EQ(j["leasing"], false);
  s.store = damaged;
  text = prometheus_text(s);
  EXPECT_NE(text.find("tessera_store_check_running 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tessera_store_damaged 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tessera_store_full 0\n"), std::string::npos) << text;
}

// A store that cannot write (a full disk): its banner state, SQLite's words and the gauge.
TEST(StoreStatus, AFullStoreReadsTheSameInTheJsonAndTheGauge) {
  StoreStatus full;
  full.write_error = "step \"INSERT INTO results ...\": database or disk is full";
  const nlohmann::json j = store_json(full);
  EXPECT_EQ(j["state"], "full");
  EXPECT_EQ(j["write_error"], full.write_error);
  EXPECT_EQ(j["leasing"], true);
  FarmSnapshotForMetrics s;
  s.store = full;
  const std::string text = prometheus_text(s);
  EXPECT_NE(text.find("# TYPE tessera_store_full gauge\ntessera_store_full 1\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("tessera_store_damaged 0\n"), std::string::npos) << text;
  // Damage outranks a full disk in the banner.
  full.damage = "database x.db is damaged";
  EXPECT_EQ(full.summary(), "damaged");
}

// A coordinator started on a store damaged where start-up does not read: its status says
// "checking" or already "damaged" at first, "damaged" once the check ended, with SQLite's
// words, leasing stopped, and how far the check had read (the pages its connection read).
TEST(StoreStatus, ACoordinatorOnADamagedStoreReportsTheCheckAndItsDamage) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("tessera-store-status-" + std::to_string(::getpid()) + ".db");
  const auto remove_db = [&] {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
  };
  remove_db();
  testing::fill_and_damage_store(path);
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = path.string();
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-store-status-test";
  {
    Coordinator coordinator(config, clock);
    const StoreStatus first = store_status(coordinator);
    EXPECT_TRUE(first.check == "checking" || first.check == "damaged") << first.check;
    ASSERT_EQ(coordinator.wait_for_store_check(), IntegrityState::damaged);
    const StoreStatus s = store_status(coordinator);
    EXPECT_EQ(s.summary(), "damaged");
    EXPECT_EQ(s.check, "damaged");
    EXPECT_NE(s.damage.find("is damaged"), std::string::npos) << s.damage;
    EXPECT_NE(s.damage.find(path.string()), std::string::npos) << s.damage;
    EXPECT_FALSE(s.leasing);
    ASSERT_TRUE(s.check_progress.has_value());
    EXPECT_GT(*s.check_progress, 0.0);  // the probe counted the pages read before the damage
    EXPECT_LE(*s.check_progress, 1.0);
  }
  remove_db();
}

// A healthy store after an unclean stop: the check passes and reads as 100 %.
TEST(StoreStatus, APassedCheckReadsAsWholeAndOk) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("tessera-store-status-ok-" + std::to_string(::getpid()) + ".db");
  const auto remove_db = [&] {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
  };
  remove_db();
  {
    Database db(path.string());
    migrate(db, 0);  // a store a server created, then left without a clean stop
  }
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = path.string();
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-store-status-test";
  {
    Coordinator coordinator(config, clock);
    ASSERT_EQ(coordinator.wait_for_store_check(), IntegrityState::ok);
    const StoreStatus s = store_status(coordinator);
    EXPECT_EQ(s.summary(), "ok");
    EXPECT_EQ(s.check, "ok");
    EXPECT_EQ(s.check_progress, 1.0);
    EXPECT_TRUE(s.leasing);
  }
  remove_db();
}

}  // namespace
}  // namespace tessera::server
