// The store's tables (server/store/): each event is a compare-and-set that changes nothing, and
// says so, when another call got there first; the reads give back what the events wrote.
#include <gtest/gtest.h>

#include "store/bundles_table.h"
#include "store/failures_table.h"
#include "store/job_clients_table.h"
#include "store/job_contributors_table.h"
#include "store/jobs_table.h"
#include "store/tiles_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

TEST(JobsTable, EachJobEventAppliesOnlyFromItsState) {
  StoreFixture f;
  JobsTable jobs(f.db);
  const int64_t id = f.make_job(16, 16, 16, 2, 1);
  EXPECT_EQ(jobs.state_and_bundle(id)->first, JobState::queued);
  EXPECT_FALSE(jobs.finish(id, "a.exr", "a.png", 5));  // queued: not running yet
  EXPECT_TRUE(jobs.start(id, 7));
  EXPECT_FALSE(jobs.start(id, 8));  // a running job stays running: the first lease dates it
  EXPECT_EQ(jobs.get(id)->started_unix_ms, 7);
  EXPECT_FALSE(jobs.cancel(id, JobState::queued, 9));  // the caller's view is stale
  EXPECT_TRUE(jobs.set_priority(id, 3));
  EXPECT_TRUE(jobs.cancel(id, JobState::running, 9));
  const JobRecord cancelled = *jobs.get(id);
  EXPECT_EQ(cancelled.state, JobState::cancelled);
  EXPECT_EQ(cancelled.finished_unix_ms, 9);
  EXPECT_EQ(cancelled.stop_reason, StopReason::cancelled);
  EXPECT_EQ(cancelled.priority, 3);
  EXPECT_FALSE(jobs.set_priority(id, 4));  // final: the priority stays
  EXPECT_FALSE(jobs.finish(id, "a.exr", "a.png", 10));
  EXPECT_FALSE(jobs.remove(id, JobState::running));
  EXPECT_TRUE(jobs.remove(id, JobState::cancelled));
  EXPECT_FALSE(jobs.get(id).has_value());
  EXPECT_FALSE(jobs.state_and_bundle(id).has_value());
}

TEST(JobsTable, CountersAddUpAndTotalsSumThem) {
  StoreFixture f;
  JobsTable jobs(f.db);
  const int64_t a = f.make_job(16, 16, 16, 2, 1);
  const int64_t b = f.make_job(16, 16, 16, 2, 1);
  jobs.count_accepted(a, 1, {2, 512, 1, 0});
  jobs.count_accepted(a, 1, {0, 0, 0, 0});  // accepted, waiting for its predecessor
  jobs.count_dropped(a);
  jobs.count_expired(b);
  jobs.count_skipped(b, 3, 1);
  const JobCounters ca = jobs.get(a)->counters;
  EXPECT_EQ(ca.units_done, 2u);
  EXPECT_EQ(ca.results_merged, 2u);
  EXPECT_EQ(ca.samples_merged, 512u);
  EXPECT_EQ(ca.nan_dropped, 1u);
  EXPECT_EQ(ca.results_dropped, 1u);
  const JobCounters cb = jobs.get(b)->counters;
  EXPECT_EQ(cb.leases_expired, 1u);
  EXPECT_EQ(cb.units_skipped, 3u);
  EXPECT_EQ(cb.results_wasted, 1u);
  const auto totals = jobs.totals_by_state();
  ASSERT_TRUE(totals.contains("queued"));
  EXPECT_EQ(totals.at("queued").jobs, 2u);
  EXPECT_EQ(totals.at("queued").units_done, 2u);
  EXPECT_EQ(totals.at("queued").leases_expired, 1u);
  EXPECT_EQ(jobs.unfinished(), (std::vector<int64_t>{a, b}));
}

JobQuery query(uint32_t limit, std::vector<JobState> states = {}, int64_t before_id = 0) {
  JobQuery q;
  q.limit = limit;
  q.states = std::move(states);
  q.before_id = before_id;
  return q;
}

/// The ids of every page of `query`, following next_before_id; `total` of each page checked.
std::vector<int64_t> every_page(JobsTable& jobs, JobQuery query, uint64_t total) {
  std::vector<int64_t> ids;
  for (int pages = 0; pages < 100; ++pages) {
    const JobPage page = jobs.page(query);
    EXPECT_EQ(page.total, total);
    EXPECT_LE(page.jobs.size(), query.limit);
    for (const JobRecord& job : page.jobs) ids.push_back(job.id);
    if (page.next_before_id == 0) break;
    EXPECT_EQ(page.next_before_id, page.jobs.back().id);
    query.before_id = page.next_before_id;
  }
  return ids;
}

TEST(JobsTable, PagesFollowTheirCursorAndCountEveryMatch) {
  StoreFixture f;
  JobsTable jobs(f.db);
  std::vector<int64_t> all, cancelled, queued_or_running;
  for (int i = 0; i < 23; ++i) {
    const int64_t id = f.make_job(8, 8, 8, 1, 1);
    if (i % 3 == 0) {
      EXPECT_TRUE(jobs.cancel(id, JobState::queued, 5));
      cancelled.insert(cancelled.begin(), id);
    } else {
      if (i == 4) {
        EXPECT_TRUE(jobs.start(id, 5));
      }
      queued_or_running.insert(queued_or_running.begin(), id);
    }
    all.insert(all.begin(), id);
  }
  // Every job once, newest first, in pages of 5; a limit that divides the count leaves no
  // empty last page.
  EXPECT_EQ(every_page(jobs, query(5), 23), all);
  EXPECT_EQ(every_page(jobs, query(23), 23), all);
  EXPECT_EQ(jobs.page(query(23)).next_before_id, 0);
  EXPECT_EQ(every_page(jobs, query(3, {JobState::cancelled}), 8), cancelled);
  // A state named twice counts once.
  const std::vector<JobState> unfinished = {JobState::running, JobState::queued,
                                            JobState::running};
  EXPECT_EQ(every_page(jobs, query(4, unfinished), 15), queued_or_running);
  EXPECT_EQ(jobs.page(query(1000, {JobState::done})).total, 0u);

  // A job submitted between two pages: the next page goes on where the last one stopped.
  const JobPage first = jobs.page(query(5));
  const int64_t newer = f.make_job(8, 8, 8, 1, 1);
  const JobPage second = jobs.page(query(5, {}, first.next_before_id));
  EXPECT_EQ(second.total, 24u);
  EXPECT_EQ(second.jobs.front().id, all[5]);
  EXPECT_EQ(jobs.page(query(1)).jobs.front().id, newer);
}

TEST(JobsTable, APageReadsItsRowsWhateverTheNumberOfJobs) {
  // A page walks the primary key from its cursor and the count is one b-tree count: the
  // statements' steps for the newest 10 are the same with 20 jobs as with 400.
  auto page_steps = [](int job_count) {
    StoreFixture f;
    for (int i = 0; i < job_count; ++i) f.make_job(8, 8, 8, 1, 1);
    JobsTable jobs(f.db);
    jobs.page(query(10));  // compiled once, outside the count
    const uint64_t before = f.db.counters().vm_steps;
    EXPECT_EQ(jobs.page(query(10)).jobs.size(), 10u);
    return f.db.counters().vm_steps - before;
  };
  const uint64_t few = page_steps(20), many = page_steps(400);
  EXPECT_GT(few, 0u);
  EXPECT_EQ(many, few);
}

TEST(TilesTable, AMergeAdvancesOnlyFromTheNextBatchItRead) {
  StoreFixture f;
  const int64_t id = f.make_job(32, 16, 16, 4, 1);
  TilesTable tiles(f.db);
  ASSERT_EQ(tiles.of_job(id).size(), 2u);
  EXPECT_EQ(tiles.rect(id, 1)->x0, 16);
  EXPECT_TRUE(tiles.advance(id, 1, 0, {2, 0.5, StopReason::none, 2}));
  EXPECT_FALSE(tiles.advance(id, 1, 0, {1, 0.5, StopReason::none, 1}));  // it moved meanwhile
  EXPECT_EQ(tiles.position(id, 1)->next_batch, 2u);
  EXPECT_FALSE(tiles.checkpoint(id, 1).has_value());
  tiles.write_checkpoint(id, 1, "sum");
  EXPECT_EQ(tiles.checkpoint(id, 1), "sum");
  EXPECT_EQ(tiles.count_finished_by(id, StopReason::max_spp), 0);
  EXPECT_TRUE(tiles.advance(id, 0, 0, {4, 0.1, StopReason::max_spp, 4}));
  EXPECT_EQ(tiles.count_finished_by(id, StopReason::max_spp), 1);
}

TEST(BundlesTable, StoredOnceAndRemovedOnlyWhenNoJobUsesIt) {
  StoreFixture f;
  BundlesTable bundles(f.db);
  const int64_t id = f.make_job(16, 16, 16, 2, 1);
  const std::string sha = JobsTable(f.db).state_and_bundle(id)->second;
  bundles.insert_once(sha, "other.json", "other bytes", 0);  // same hash: kept as first stored
  EXPECT_EQ(bundles.bytes(sha), "bundle of job 1");
  EXPECT_FALSE(bundles.remove_unused(sha));  // job 1 uses it
  ASSERT_EQ(f.jobs.cancel(id, 0), CancelOutcome::cancelled);
  ASSERT_TRUE(JobsTable(f.db).remove(id, JobState::cancelled));
  EXPECT_TRUE(bundles.remove_unused(sha));
  EXPECT_FALSE(bundles.bytes(sha).has_value());
}

TEST(JobClientsAndContributors, QuotaCountsUnfinishedJobsAndProvenanceIsDistinct) {
  StoreFixture f;
  const int64_t a = f.make_job(16, 16, 16, 2, 1);
  const int64_t b = f.make_job(16, 16, 16, 2, 1);
  JobClientsTable clients(f.db);
  clients.add(a, "alice");
  clients.add(b, "alice");
  EXPECT_EQ(clients.unfinished_of("alice"), 2u);
  ASSERT_EQ(f.jobs.cancel(a, 0), CancelOutcome::cancelled);
  EXPECT_EQ(clients.unfinished_of("alice"), 1u);
  EXPECT_EQ(clients.unfinished_of("bob"), 0u);

  const int64_t w = f.workers.register_worker({"w", 1, "avx2", "1.2"}, 0);
  JobContributorsTable contributors(f.db);
  contributors.add(b, "avx2", w);
  contributors.add(b, "avx2", w);
  contributors.add(b, "sse4.2", w);
  EXPECT_EQ(contributors.isas(b), (std::vector<std::string>{"avx2", "sse4.2"}));
  EXPECT_EQ(contributors.versions(b), (std::vector<std::string>{"1.2"}));
}

}  // namespace
}  // namespace tessera::server
