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

}  // namespace
}  // namespace tessera::client
