// Long job lists end to end: more jobs than a page, listed through JobService.ListJobs, the
// dashboard's /api/jobs and `tessera list`. Each gives the total, pages that cover every job
// exactly once (newest first, following the cursor), the state filter, a bounded page, and a
// refusal naming the field for a bad limit, state or cursor. The jobs are tiny and never run (no
// worker): submitting them is the test's cost.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

using nlohmann::json;

/// Submits `count` tiny jobs over gRPC; returns their ids, oldest first.
std::vector<uint64_t> submit_tiny_jobs(FarmCluster& farm, int count) {
  std::ifstream in(source_dir() / "tests" / "farm" / "data" / "tiny.json");
  v1::SubmitJobRequest request;
  request.mutable_bundle()->set_scene_file("tiny.json");
  auto* file = request.mutable_bundle()->add_files();
  file->set_path("tiny.json");
  file->set_data(std::string(std::istreambuf_iterator<char>(in), {}));
  request.mutable_options()->set_spp(1);
  std::vector<uint64_t> ids;
  for (int i = 0; i < count; ++i) {
    v1::SubmitJobResponse response;
    const grpc::Status status =
        farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    ids.push_back(response.job().id());
  }
  return ids;
}

/// ListJobs of `request`, which must succeed.
v1::ListJobsResponse list_jobs(FarmCluster& farm, const v1::ListJobsRequest& request) {
  v1::ListJobsResponse response;
  const grpc::Status status =
      farm.jobs().ListJobs(FarmCluster::context().get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response;
}

/// Every page of `request` over gRPC, following next_before_id: the ids in order. Each page
/// must hold at most its limit and say `total`.
std::vector<uint64_t> every_grpc_page(FarmCluster& farm, v1::ListJobsRequest request,
                                      uint64_t total) {
  std::vector<uint64_t> ids;
  for (int pages = 0; pages < 100; ++pages) {
    const v1::ListJobsResponse page = list_jobs(farm, request);
    EXPECT_EQ(page.total(), total);
    EXPECT_LE(uint32_t(page.jobs_size()), request.limit());
    for (const v1::JobInfo& job : page.jobs()) ids.push_back(job.id());
    if (page.next_before_id() == 0) break;
    request.set_before_id(page.next_before_id());
  }
  return ids;
}

std::vector<uint64_t> newest_first(std::vector<uint64_t> ids) {
  std::sort(ids.rbegin(), ids.rend());
  return ids;
}

class JobList : public ::testing::Test {
 protected:
  void SetUp() override {
    farm_ = std::make_unique<FarmCluster>("job-list");
    farm_->start_server({"--max-queued-jobs", "0"});
    all_ = submit_tiny_jobs(*farm_, 25);
    // Every fourth job cancelled: 7 of 25.
    for (size_t i = 0; i < all_.size(); i += 4) {
      v1::CancelJobRequest cancel;
      cancel.set_job_id(all_[i]);
      v1::JobInfo info;
      ASSERT_TRUE(farm_->jobs().CancelJob(FarmCluster::context().get(), cancel, &info).ok());
      cancelled_.push_back(all_[i]);
    }
    for (const uint64_t id : all_) {
      if (std::find(cancelled_.begin(), cancelled_.end(), id) == cancelled_.end()) {
        queued_.push_back(id);
      }
    }
  }

  /// GET `path` on the dashboard; the answer's status must be `status`.
  json get_json(const std::string& path, int status = 200) {
    httplib::Client c("127.0.0.1", farm_->http_port());
    c.set_read_timeout(60, 0);
    httplib::Result r = c.Get(path.c_str());
    if (!r) {
      ADD_FAILURE() << path << ": " << httplib::to_string(r.error());
      return {};
    }
    EXPECT_EQ(r->status, status) << path << ": " << r->body;
    return json::parse(r->body, nullptr, false);
  }

  /// Every page of /api/jobs?QUERY&limit=LIMIT, following next_before: the ids in order.
  std::vector<uint64_t> every_api_page(const std::string& query, size_t limit, uint64_t total) {
    std::vector<uint64_t> ids;
    std::string before;
    for (int pages = 0; pages < 100; ++pages) {
      const json page = get_json("/api/jobs?limit=" + std::to_string(limit) + query + before);
      EXPECT_EQ(page["total"], total);
      EXPECT_LE(page["jobs"].size(), limit);
      for (const json& job : page["jobs"]) ids.push_back(job["id"].get<uint64_t>());
      if (page["next_before"].is_null()) break;
      before = "&before=" + std::to_string(page["next_before"].get<uint64_t>());
    }
    return ids;
  }

  std::unique_ptr<FarmCluster> farm_;
  std::vector<uint64_t> all_, cancelled_, queued_;  ///< oldest first
};

TEST_F(JobList, GrpcPagesCoverEveryJobOnceWithTheTotalAndTheStateFilter) {
  v1::ListJobsRequest request;
  request.set_limit(7);
  EXPECT_EQ(every_grpc_page(*farm_, request, 25), newest_first(all_));
  request.add_states(v1::JOB_STATE_CANCELLED);
  request.set_limit(3);
  EXPECT_EQ(every_grpc_page(*farm_, request, 7), newest_first(cancelled_));
  request.add_states(v1::JOB_STATE_QUEUED);
  EXPECT_EQ(every_grpc_page(*farm_, request, 25), newest_first(all_));
  request.clear_states();
  request.add_states(v1::JOB_STATE_QUEUED);
  request.set_limit(0);  // the default: 1000
  const v1::ListJobsResponse queued = list_jobs(*farm_, request);
  EXPECT_EQ(queued.total(), 18u);
  EXPECT_EQ(queued.jobs_size(), 18);
  EXPECT_EQ(queued.next_before_id(), 0u);
  // An old client's request (no states, no cursor): the newest 1000, with the total.
  EXPECT_EQ(list_jobs(*farm_, {}).jobs_size(), 25);

  auto refused = [&](const v1::ListJobsRequest& bad, const std::string& field) {
    v1::ListJobsResponse response;
    const grpc::Status status =
        farm_->jobs().ListJobs(FarmCluster::context().get(), bad, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << field;
    EXPECT_EQ(status.error_message().rfind(field, 0), 0u) << status.error_message();
  };
  v1::ListJobsRequest bad;
  bad.set_limit(1001);
  refused(bad, "limit must be 0..1000");
  bad.Clear();
  bad.add_states(v1::JOB_STATE_UNSPECIFIED);
  refused(bad, "states: 0 is not a job state");
  bad.Clear();
  bad.add_states(v1::JobState(42));
  refused(bad, "states: 42 is not a job state");
  bad.Clear();
  bad.set_before_id(uint64_t(INT64_MAX) + 1);
  refused(bad, "before_id must be");
}

TEST_F(JobList, ApiPagesCarryTheTotalAndTheNextCursor) {
  EXPECT_EQ(every_api_page("", 7, 25), newest_first(all_));
  EXPECT_EQ(every_api_page("&state=cancelled", 2, 7), newest_first(cancelled_));
  EXPECT_EQ(every_api_page("&state=queued,cancelled", 10, 25), newest_first(all_));
  EXPECT_EQ(every_api_page("&state=queued&state=cancelled", 25, 25), newest_first(all_));
  // A page is bounded whatever the number of jobs: at most its limit, at most 1000.
  const json first = get_json("/api/jobs?limit=5");
  EXPECT_EQ(first["jobs"].size(), 5u);
  EXPECT_EQ(first["next_before"], all_[20]);
  EXPECT_EQ(get_json("/api/jobs")["jobs"].size(), 25u);  // the default limit, 1000
  EXPECT_TRUE(get_json("/api/jobs?state=running")["jobs"].empty());
  EXPECT_EQ(get_json("/api/jobs?state=running")["total"], 0);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"limit=0", "limit must be 1..1000 (got \"0\")"},
      {"limit=1001", "limit must be 1..1000"},
      {"limit=ten", "limit must be"},
      {"before=0", "before must be"},
      {"before=-3", "before must be"},
      {"state=paused", "state must be queued, running, done, failed or cancelled"},
      {"state=queued,", "state must be"},
      {"state=", "state must be"},
  };
  for (const auto& [query, error] : bad) {
    const json answer = get_json("/api/jobs?" + query, 400);
    ASSERT_TRUE(answer.contains("error")) << query;
    EXPECT_EQ(answer["error"].get<std::string>().rfind(error, 0), 0u) << answer;
  }
}

TEST_F(JobList, TheCliShowsAPageSaysWhatItLeftOutAndFiltersByState) {
  const CommandResult ten = farm_->cli({"list", "--limit", "10"});
  ASSERT_EQ(ten.exit_code, 0) << ten.err;
  // The header, 10 jobs, and what was left out.
  EXPECT_EQ(std::count(ten.out.begin(), ten.out.end(), '\n'), 12) << ten.out;
  EXPECT_NE(ten.out.find("\nshowing 10 of 25 jobs (--all for every job, --limit N for more)\n"),
            std::string::npos)
      << ten.out;

  auto ids_of = [](const CommandResult& r) {
    std::vector<uint64_t> ids;
    for (const json& job : json::parse(r.out)) ids.push_back(job["id"].get<uint64_t>());
    return ids;
  };
  const CommandResult three = farm_->cli({"list", "--limit", "3", "--json"});
  ASSERT_EQ(three.exit_code, 0) << three.err;
  EXPECT_EQ(ids_of(three), (std::vector<uint64_t>{all_[24], all_[23], all_[22]}));
  EXPECT_NE(three.err.find("showing 3 of 25 jobs"), std::string::npos) << three.err;

  const CommandResult cancelled = farm_->cli({"list", "--state", "cancelled", "--json"});
  ASSERT_EQ(cancelled.exit_code, 0) << cancelled.err;
  EXPECT_EQ(ids_of(cancelled), newest_first(cancelled_));
  EXPECT_EQ(cancelled.err, "");  // every match shown: nothing to say
  const CommandResult both =
      farm_->cli({"list", "--state", "cancelled,queued", "--limit", "24"});
  EXPECT_NE(both.out.find("showing 24 of 25 cancelled or queued jobs"), std::string::npos)
      << both.out;
  const CommandResult repeated =
      farm_->cli({"list", "--state", "queued", "--state", "cancelled", "--all", "--json"});
  EXPECT_EQ(ids_of(repeated), newest_first(all_));

  for (const std::vector<std::string>& usage :
       {std::vector<std::string>{"list", "--state", "paused"},
        std::vector<std::string>{"list", "--limit", "0"},
        std::vector<std::string>{"list", "--all", "--limit", "5"}}) {
    const CommandResult r = farm_->cli(usage);
    EXPECT_EQ(r.exit_code, 2) << usage[1] << ": " << r.err;
    EXPECT_NE(r.err.find(usage[1]), std::string::npos) << r.err;
  }
}

// More jobs than ListJobs' largest page (1000): `--all` and a --limit past one page follow the
// cursor; the default shows the newest 100 and says how many there are.
TEST(JobListE2E, TheCliFollowsTheCursorPastOnePage) {
  FarmCluster farm("job-list-pages");
  farm.start_server({"--max-queued-jobs", "0"});
  const std::vector<uint64_t> all = submit_tiny_jobs(farm, 1010);

  const CommandResult every = farm.cli({"list", "--all", "--json"});
  ASSERT_EQ(every.exit_code, 0) << every.err;
  std::vector<uint64_t> ids;
  for (const json& job : json::parse(every.out)) ids.push_back(job["id"].get<uint64_t>());
  EXPECT_EQ(ids, newest_first(all));
  EXPECT_EQ(every.err, "");

  const CommandResult more = farm.cli({"list", "--limit", "1005", "--json"});
  ASSERT_EQ(more.exit_code, 0) << more.err;
  const json page = json::parse(more.out);
  ASSERT_EQ(page.size(), 1005u);
  EXPECT_EQ(page.back()["id"], all[5]);
  EXPECT_NE(more.err.find("showing 1005 of 1010 jobs"), std::string::npos) << more.err;

  const CommandResult newest = farm.cli({"list"});
  ASSERT_EQ(newest.exit_code, 0) << newest.err;
  EXPECT_EQ(std::count(newest.out.begin(), newest.out.end(), '\n'), 102) << newest.out;
  EXPECT_NE(newest.out.find("showing 100 of 1010 jobs"), std::string::npos) << newest.out;
}

}  // namespace
}  // namespace tessera::e2e
