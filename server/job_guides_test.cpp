// A denoise job's guides as the server merges them (job_guides.h): the stored rows of a tile's
// merged batches added in batch order, as the local render adds them; a missing row refused.
// Guides uploaded with a result are stored only where the unit asked for them.
// The JobDenoise refusals that need no library: an unloadable library, a working set over the
// server's memory budget (checked first).
#include "job_guides.h"

#include <gtest/gtest.h>

#include <cstring>

#include "accum/guide_tile_codec.h"
#include "farm_error.h"
#include "job_denoise.h"
#include "store/guide_results_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

/// A guide tile of `rect` whose sums depend on `batch` (so that the merge order shows).
GuideTile guide_tile_of_batch(const TileRect& rect, uint32_t batch) {
  GuideTile g(rect);
  for (size_t i = 0; i < g.albedo.size(); ++i) {
    g.albedo[i] = 0.1 + 1e-3 * double(batch) + 1e-9 * double(i);
    g.normal[i] = -0.3 + 1e-4 * double(batch * 7 + i);
  }
  for (uint32_t& n : g.count) n = 16;
  return g;
}

JobPlan guide_test_plan() {
  JobOptions o;
  o.width = 16;
  o.height = 8;
  o.spp = 80;
  o.batch_spp = 16;  // batches 0-3 below kGuideSamples (64), batch 4 not
  o.tile_size = 8;
  return o.plan();
}

TEST(JobGuides, MergesTheMergedBatchesRowsInBatchOrderAsTheLocalRender) {
  const TileRect rect{8, 0, 16, 8};
  const TilePosition at{rect, 5};
  GuideRows rows;
  GuideTile local;  // worker/local_render.cpp: a default tile, then each batch merged in order
  for (uint32_t b = 0; b < 4; ++b) {
    rows.emplace_back(b, encode_guide_tile(guide_tile_of_batch(rect, b)));
    local.merge(guide_tile_of_batch(rect, b));
  }
  const GuideTile merged = merge_tile_guides(1, 1, at, guide_test_plan(), rows);
  ASSERT_EQ(merged.albedo.size(), local.albedo.size());
  EXPECT_EQ(std::memcmp(merged.albedo.data(), local.albedo.data(), local.albedo.size() * 8), 0);
  EXPECT_EQ(std::memcmp(merged.normal.data(), local.normal.data(), local.normal.size() * 8), 0);
  EXPECT_EQ(merged.count, local.count);

  // Two batches merged: only their rows count.
  const GuideTile two = merge_tile_guides(1, 1, {rect, 2}, guide_test_plan(), {rows[0], rows[1]});
  EXPECT_EQ(two.count.front(), 32u);
  // Nothing merged: an empty tile (black guides).
  EXPECT_TRUE(merge_tile_guides(1, 1, {rect, 0}, guide_test_plan(), {}).count.empty());
}

TEST(JobGuides, RefusesAMergedBatchWithoutItsGuides) {
  const TileRect rect{0, 0, 8, 8};
  GuideRows rows{{0, encode_guide_tile(guide_tile_of_batch(rect, 0))},
                 {2, encode_guide_tile(guide_tile_of_batch(rect, 2))}};
  try {
    merge_tile_guides(7, 3, {rect, 3}, guide_test_plan(), rows);
    FAIL() << "merged without batch 1's guides";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "job 7 tile 3: no guides for merged batch 1 (rendered by a worker without them?)");
  }
}

/// A result of `lease` (4x4 tile, 1 spp) carrying guides.
UnitResult guided_result_for(const Lease& lease, Accumulation& acc) {
  acc = testing::StoreFixture::synthetic({0, 0, 4, 4}, lease.batch, 1);
  UnitResult r = testing::result_for(lease, acc);
  r.guides = encode_guide_tile(guide_tile_of_batch({0, 0, 4, 4}, lease.batch));
  return r;
}

TEST(JobGuides, StoredForADenoiseJobRefusedForAnother) {
  testing::StoreFixture f;
  const int64_t plain = f.make_job(4, 4, 4, 2, 1);
  const int64_t w = f.make_worker();
  Accumulation acc;
  const Lease plain_lease = *f.book.lease_next(w);
  ASSERT_EQ(plain_lease.job_id, plain);
  try {
    f.merger.accept(guided_result_for(plain_lease, acc), acc);
    FAIL() << "guides stored for a job without denoise";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("did not ask for"), std::string::npos) << e.what();
  }
  // The lease stays current: the same result without guides is accepted.
  Accumulation again = testing::StoreFixture::synthetic({0, 0, 4, 4}, 0, 1);
  EXPECT_TRUE(f.merger.accept(testing::result_for(plain_lease, again), again).accepted);

  f.db.prepare("UPDATE jobs SET denoise = 1 WHERE id = ?")->bind(1, plain).run();
  const Lease next = *f.book.lease_next(w);
  EXPECT_TRUE(f.merger.accept(guided_result_for(next, acc), acc).accepted);
  std::vector<uint32_t> stored;
  GuideResultsTable(f.db).for_each_below(plain, 0, 2, [&](uint32_t b, const std::string&) {
    stored.push_back(b);
  });
  EXPECT_EQ(stored, std::vector<uint32_t>{next.batch});
}

TEST(JobDenoiseRefusals, AMissingLibraryRefusesAtSubmitNamingTheFlag) {
  const JobDenoise denoise({"/nonexistent/libOpenImageDenoise.so.2"}, nullptr);
  EXPECT_NE(denoise.unavailable().find("--oidn-library"), std::string::npos);
  try {
    denoise.check_submit(64, 64);
    FAIL() << "accepted without a library";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::failed_precondition);
    EXPECT_EQ(std::string(e.what()).rfind("the server cannot denoise: ", 0), 0u) << e.what();
  }
}

TEST(JobDenoiseRefusals, AWorkingSetOverTheMemoryBudgetIsRefused) {
  SubmitBudget budget(uint64_t(512) << 20);
  const JobDenoise denoise({"/nonexistent/libOpenImageDenoise.so.2"}, &budget);
  EXPECT_LT(JobDenoise::working_set_bytes(640, 480), uint64_t(512) << 20);
  try {
    denoise.check_submit(4096, 4096);
    FAIL() << "accepted a denoise larger than the budget";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("--submit-memory-mb"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tessera::server
