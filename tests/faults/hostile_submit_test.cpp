// Hostile input at the server (docs/reliability.md, "Hostile input"): the scenes of
// tests/render/bad/hostile sent straight to a real tessera-server with SubmitJob, as a client
// that skips the CLI's local validation would, with the files they name in the bundle. Each is
// refused with INVALID_ARGUMENT and a one-line reason; nothing is stored or scheduled; the server
// keeps serving and renders a good job afterwards. (tests/render/CMakeLists.txt checks the same
// scenes against `tessera-worker render` and `tessera submit`.)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

struct Hostile {
  std::string scene;                                         ///< in tests/render/bad/hostile
  std::vector<std::pair<std::string, std::string>> files;    ///< bundle path -> file on disk
  std::string reason;                                        ///< regex over the status message
};

TEST(HostileInput, ServerRefusesEveryHostileBundleWithItsReasonAndKeepsServing) {
  FarmCluster farm("hostile");
  farm.start_server();
  const auto dir = source_dir() / "tests" / "render" / "bad" / "hostile";
  const std::vector<Hostile> cases = {
      {"huge_number.json", {}, "shapes\\[0\\]\\.radius: must be a finite number"},
      {"huge_spp.json", {}, "render\\.spp: is too large"},
      {"huge_film.json", {}, "film\\.width: must be in \\[1, 32768\\]"},
      {"huge_index.json", {}, "shapes\\[0\\]\\.indices\\[0\\]\\[2\\]: index 4294967295 out of range"},
      {"nan_literal.json", {}, "line 8, column 39: .*invalid literal"},
      {"not_utf8.json", {}, "line 6, .*UTF-8"},
      {"empty.json", {}, "line 1, column 1: .*unexpected end of input"},
      {"deep_nesting.json", {}, "x: unknown key"},
      {"deep_nesting_unclosed.json", {}, "line 2, column 1: .*unexpected end of input"},
      {"ply_1e8_triangles.json", {{"1e8_triangles.ply", "1e8_triangles.ply"}},
       "element \"face\" declares 100000000 rows, which cannot fit"},
      {"ply_1e9_triangles.json", {{"1e9_triangles.ply", "1e9_triangles.ply"}},
       "element \"face\" declares 1000000000 rows"},
      {"ply_truncated.json", {{"truncated.ply", "truncated.ply"}},
       "truncated\\.ply: line 13 \\(element vertex, row 2\\): unexpected end of file"},
      {"ply_bad_index.json", {{"bad_index.ply", "bad_index.ply"}}, "vertex index 7 out of range"},
      {"obj_bad_index.json", {{"bad_index.obj", "bad_index.obj"}}, "refers to vertex 99999"},
      {"traversal_dotdot.json", {}, "shapes\\[0\\]\\.file: path must stay inside"},
      // The same path as a file of the bundle: refused before the scene is read.
      {"traversal_dotdot.json", {{"meshes/../../../../etc/passwd.ply", "bad_index.ply"}},
       "bundle"},
      // A client that follows the symlink sends the target's bytes: not a mesh.
      {"traversal_symlink.json", {{"outside_link.ply", "outside_link.ply"}}, "outside_link\\.ply: "},
      {"traversal_mtl.json", {{"escaping_mtl.obj", "escaping_mtl.obj"}},
       "mtllib: path must stay inside"},
  };
  for (const Hostile& h : cases) {
    SCOPED_TRACE(h.scene + " with " + std::to_string(h.files.size()) + " extra file(s)");
    v1::SubmitJobRequest request;
    request.mutable_bundle()->set_scene_file(h.scene);
    auto* scene = request.mutable_bundle()->add_files();
    scene->set_path(h.scene);
    scene->set_data(read_text(dir / h.scene));
    for (const auto& [path, disk] : h.files) {
      auto* f = request.mutable_bundle()->add_files();
      f->set_path(path);
      f->set_data(read_text(dir / disk));
    }
    v1::SubmitJobResponse response;
    const grpc::Status status =
        farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_TRUE(std::regex_search(status.error_message(), std::regex(h.reason)))
        << status.error_message();
    EXPECT_EQ(status.error_message().find('\n'), std::string::npos) << status.error_message();
  }
  // Nothing was stored or scheduled, and the server still renders a good job.
  const CommandResult list = farm.cli({"list", "--json"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(nlohmann::json::parse(list.out).empty()) << list.out;
  farm.start_worker({"--threads", "1"});
  const uint64_t id = farm.submit({(source_dir() / "tests" / "render" / "bad" / "good.json").string()});
  const v1::JobInfo job = farm.wait_final(id);
  EXPECT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_EQ(job.counters().results_merged(), job.counters().units_total());
}

}  // namespace
}  // namespace tessera::e2e

namespace tessera::e2e {
namespace {

// A result is hostile input too: huge_result.acc is 19,029 bytes whose header declares a
// 4096x4096 rectangle and whose zstd frame of zeros really holds the 604 MB that needs. Decoded
// on trust it took the server to 1.7 GB of RSS; the server must refuse it from the header,
// because the unit's tile is 8x8 (docs/reliability.md, "A hostile result").
TEST(HostileInput, ResultDeclaringAHugeRectangleIsRefusedBeforeDecoding) {
  FarmCluster farm("hostile-result");
  farm.start_server();
  const auto good = source_dir() / "tests" / "render" / "bad" / "good.json";
  const uint64_t id = farm.submit({good.string(), "--tile", "16"});
  ASSERT_NE(id, 0u);
  v1::RegisterRequest reg;
  reg.set_name("hostile");
  reg.set_threads(1);
  v1::RegisterResponse me;
  ASSERT_TRUE(farm.workers_api().Register(FarmCluster::context().get(), reg, &me).ok());
  v1::UploadResultRequest up;
  up.set_worker_id(me.worker_id());
  up.set_lease_id(std::string(32, 'a'));
  up.set_job_id(id);
  up.set_tile(0);
  up.set_batch(0);
  up.set_accumulation(read_text(source_dir() / "tests" / "render" / "bad" / "hostile" / "huge_result.acc"));
  v1::UploadResultResponse response;
  const grpc::Status status = farm.workers_api().UploadResult(FarmCluster::context().get(), up, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_NE(status.error_message().find("4096x4096 has more pixels than the limit of 64"),
            std::string::npos)
      << status.error_message();
  // The job is untouched: nothing accepted, nothing dropped.
  const v1::JobInfo job = farm.job(id);
  EXPECT_EQ(job.counters().units_done(), 0u);
  EXPECT_EQ(job.counters().results_dropped(), 0u);
}

}  // namespace
}  // namespace tessera::e2e
