// The --json form of `tessera workers` (client/json_view.h).
#include "json_view.h"

#include <gtest/gtest.h>

namespace tessera::client {
namespace {

TEST(WorkersJson, AnIdleWorkerHasNoJobTileOrBatch) {
  v1::WorkerInfo idle;
  idle.set_id(3);
  const nlohmann::json j = to_json(idle);
  EXPECT_TRUE(j.at("job_id").is_null());
  EXPECT_TRUE(j.at("tile").is_null());
  EXPECT_TRUE(j.at("batch").is_null());
}

TEST(WorkersJson, ABusyWorkerNamesItsUnitEvenTileAndBatchZero) {
  v1::WorkerInfo busy;
  busy.set_job_id(7);
  busy.set_tile(0);
  busy.set_batch(0);
  busy.set_units_held(2);
  const nlohmann::json j = to_json(busy);
  EXPECT_EQ(j.at("job_id"), 7);
  EXPECT_EQ(j.at("tile"), 0);
  EXPECT_EQ(j.at("batch"), 0);
  EXPECT_EQ(j.at("units_held"), 2);
}

TEST(WorkersJson, AQuarantinedWorkerSaysWhereAndWhyAndAnOtherHasNullQuarantine) {
  v1::WorkerInfo w;
  w.set_state("quarantined");
  w.set_checks(1);
  w.set_mismatches(1);
  v1::WorkerQuarantine* q = w.mutable_quarantine();
  q->set_job_id(4);
  q->set_tile(2);
  q->set_batch(0);
  q->set_time_unix_ms(1000);
  q->set_reason("its result of job 4 tile 2 batch 0 differs from 2 other workers'");
  q->add_finished_jobs(1);
  const nlohmann::json j = to_json(w);
  EXPECT_EQ(j.at("state"), "quarantined");
  EXPECT_EQ(j.at("quarantine").at("job"), 4);
  EXPECT_EQ(j.at("quarantine").at("tile"), 2);
  EXPECT_EQ(j.at("quarantine").at("reason"), q->reason());
  EXPECT_EQ(j.at("quarantine").at("finished_jobs"), nlohmann::json::array({1}));
  EXPECT_EQ(j.at("mismatches"), 1);
  v1::WorkerInfo online;
  online.set_online(true);  // a server from before spot checks sends no state
  EXPECT_EQ(to_json(online).at("state"), "online");
  EXPECT_TRUE(to_json(online).at("quarantine").is_null());
}

}  // namespace
}  // namespace tessera::client
