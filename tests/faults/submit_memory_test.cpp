// Submit checks under the server's memory budget (docs/farm.md, "The server's memory"): bundles
// built here, sent straight to a real tessera-server with SubmitJob several at once, as a client
// that skips the CLI's local checks would. The server's peak resident memory (VmHWM, Linux) and
// the budget's own peak (/metrics) stay under bounds; nothing here depends on timing.
#include <gtest/gtest.h>
#include <httplib.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <future>
#include <regex>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

constexpr uint64_t kSubmitTestMiB = uint64_t(1) << 20;
/// The budget the tests give the server: small, so that the sanitizer build fits too.
constexpr uint64_t kSubmitTestBudgetMiB = 384;
/// The server's peak resident memory may reach its budget plus this much (its own code, gRPC's
/// copies of the requests, sanitizer overhead). Unbounded, one 0.5 MB bomb took it to 1.8 GB.
constexpr uint64_t kSubmitTestSlackMiB = 640;

/// VmHWM of process `pid` in bytes (0 where /proc has no such line).
uint64_t submit_test_vm_hwm(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;  // kB
  }
  return 0;
}

/// A Mitsuba serialized file (version 4) of one float shape declaring `vertices` and
/// `triangles`, whose compressed stream holds the header then `write(z)` feeding the arrays.
template <typename Write>
std::string submit_test_serialized(uint64_t vertices, uint64_t triangles, Write write) {
  z_stream z{};
  EXPECT_EQ(deflateInit(&z, 6), Z_OK);
  std::string out;
  auto feed = [&](const void* data, size_t size, int flush) {
    z.next_in = static_cast<Bytef*>(const_cast<void*>(data));
    z.avail_in = uInt(size);
    do {
      unsigned char chunk[1 << 16];
      z.next_out = chunk;
      z.avail_out = sizeof chunk;
      deflate(&z, flush);
      out.append(reinterpret_cast<char*>(chunk), sizeof chunk - z.avail_out);
    } while (z.avail_out == 0 || (flush == Z_FINISH && z.avail_in > 0));
  };
  std::string head(4, '\0');
  const uint32_t flags = 0x1000;  // float positions, no normals or uvs
  std::memcpy(head.data(), &flags, 4);
  head += "mesh";
  head += '\0';
  head.append(reinterpret_cast<const char*>(&vertices), 8);
  head.append(reinterpret_cast<const char*>(&triangles), 8);
  feed(head.data(), head.size(), Z_NO_FLUSH);
  write(feed);
  feed(nullptr, 0, Z_FINISH);
  deflateEnd(&z);
  std::string file("\x1c\x04\x04\x00", 4);
  return file + out;
}

/// The 20M-vertex, 20M-triangle mesh of zeros: about 466 KB that declare 480 MB of arrays.
std::string submit_test_zero_bomb() {
  const uint64_t count = 20'000'000;
  return submit_test_serialized(count, count, [&](auto& feed) {
    const std::string zeros(1 << 20, '\0');
    for (uint64_t left = count * 24; left > 0;) {
      const size_t n = size_t(std::min<uint64_t>(left, zeros.size()));
      feed(zeros.data(), n, Z_NO_FLUSH);
      left -= n;
    }
  });
}

/// A valid mesh of `n` vertices in the unit cube and `n` triangles, pseudo-random from `seed` so
/// that it does not compress (its file is about 24 bytes a vertex).
std::string submit_test_noise_mesh(uint32_t n, uint32_t seed) {
  return submit_test_serialized(n, n, [&](auto& feed) {
    uint32_t x = seed;
    auto next = [&x] { return x = x * 1664525u + 1013904223u; };
    std::vector<float> positions(size_t(3) * n);
    for (float& p : positions) p = float(next() >> 8) / float(1 << 24);
    feed(positions.data(), positions.size() * 4, Z_NO_FLUSH);
    std::vector<uint32_t> indices(size_t(3) * n);
    for (uint32_t& i : indices) i = next() % n;
    feed(indices.data(), indices.size() * 4, Z_NO_FLUSH);
  });
}

v1::SubmitJobRequest submit_test_request(const std::string& mesh) {
  v1::SubmitJobRequest request;
  v1::SceneBundle& bundle = *request.mutable_bundle();
  bundle.set_scene_file("scene.xml");
  auto* scene = bundle.add_files();
  scene->set_path("scene.xml");
  scene->set_data(R"(<scene version="3.0.0">
    <sensor type="perspective">
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="16"/>
        </film>
    </sensor>
    <shape type="serialized"><string name="filename" value="mesh.serialized"/></shape>
    <emitter type="constant"/>
</scene>
)");
  auto* file = bundle.add_files();
  file->set_path("mesh.serialized");
  file->set_data(mesh);
  return request;
}

/// Sends every request at once, each on its own thread; returns their statuses.
std::vector<grpc::Status> submit_test_all_at_once(
    FarmCluster& farm, const std::vector<v1::SubmitJobRequest>& requests) {
  std::vector<std::future<grpc::Status>> calls;
  for (const v1::SubmitJobRequest& request : requests) {
    calls.push_back(std::async(std::launch::async, [&farm, &request] {
      v1::SubmitJobResponse response;
      return farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
    }));
  }
  std::vector<grpc::Status> statuses;
  for (auto& call : calls) statuses.push_back(call.get());
  return statuses;
}

/// A value of the server's /metrics.
uint64_t submit_test_metric(const FarmCluster& farm, const std::string& name) {
  httplib::Client http("127.0.0.1", farm.http_port());
  const httplib::Result metrics = http.Get("/metrics");
  EXPECT_TRUE(metrics && metrics->status == 200);
  if (!metrics) return 0;
  const std::regex line("(^|\n)" + name + " ([0-9]+)\n");
  std::smatch match;
  EXPECT_TRUE(std::regex_search(metrics->body, match, line))
      << name << " not in\n" << metrics->body;
  return match.empty() ? 0 : std::stoull(match[2]);
}

TEST(SubmitMemory, ZeroMeshBombsAreRefusedFromTheirHeaderInBoundedMemory) {
  FarmCluster farm("submit-bomb");
  farm.start_server({"--submit-memory-mb", std::to_string(kSubmitTestBudgetMiB)});
  const std::string bomb = submit_test_zero_bomb();
  ASSERT_LT(bomb.size(), 600'000u);
  const uint64_t before = submit_test_vm_hwm(farm.server_pid());
  const std::vector<grpc::Status> statuses =
      submit_test_all_at_once(farm, std::vector(4, submit_test_request(bomb)));
  for (const grpc::Status& status : statuses) {
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_NE(status.error_message().find("mesh.serialized: 20000000 vertices and 20000000 "
                                          "triangles (480000000 bytes) declared in "),
              std::string::npos)
        << status.error_message();
  }
  const uint64_t after = submit_test_vm_hwm(farm.server_pid());
  std::cout << "server VmHWM: " << before / kSubmitTestMiB << " MiB before, "
            << after / kSubmitTestMiB << " MiB after four bombs of " << bomb.size()
            << " bytes at once\n";
  if (after > 0) {
    EXPECT_LT(after, (kSubmitTestBudgetMiB + kSubmitTestSlackMiB) * kSubmitTestMiB);
  }
  // Refused from the header, the bombs reserved only their bytes.
  EXPECT_LT(submit_test_metric(farm, "tessera_submit_memory_peak_bytes"), 16 * kSubmitTestMiB);
}

TEST(SubmitMemory, ConcurrentSubmitsShareTheBudgetAndOneLargerThanItIsRefused) {
  FarmCluster farm("submit-budget");
  farm.start_server({"--submit-memory-mb", std::to_string(kSubmitTestBudgetMiB)});
  // Each bundle: 1M vertices and triangles in about 24 MB, reserving 3 x 24 MB for its bytes
  // and 3 x 36 MB for its arrays: two fit in the budget at once, not three.
  std::vector<v1::SubmitJobRequest> requests;
  for (uint32_t i = 0; i < 4; ++i) {
    requests.push_back(submit_test_request(submit_test_noise_mesh(1'000'000, 7 + i)));
  }
  const std::vector<grpc::Status> statuses = submit_test_all_at_once(farm, requests);
  int accepted = 0;
  for (const grpc::Status& status : statuses) {
    // A submit waits up to 60 s for the budget; one not served by then is told to try again.
    if (status.ok()) {
      ++accepted;
    } else {
      EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
          << status.error_message();
      EXPECT_NE(status.error_message().find("--submit-memory-mb"), std::string::npos)
          << status.error_message();
    }
  }
  EXPECT_GE(accepted, 1);
  const uint64_t peak = submit_test_metric(farm, "tessera_submit_memory_peak_bytes");
  EXPECT_LE(peak, kSubmitTestBudgetMiB * kSubmitTestMiB);
  EXPECT_GE(peak, 170 * kSubmitTestMiB);  // one bundle's reservation, at least
  EXPECT_EQ(submit_test_metric(farm, "tessera_submit_memory_reserved_bytes"), 0u);
  const uint64_t hwm = submit_test_vm_hwm(farm.server_pid());
  std::cout << "server VmHWM: " << hwm / kSubmitTestMiB << " MiB after four 24 MB meshes at once\n";
  if (hwm > 0) {
    EXPECT_LT(hwm, (kSubmitTestBudgetMiB + kSubmitTestSlackMiB) * kSubmitTestMiB);
  }

  // Three times the mesh: more than the whole budget, refused before anything is decoded,
  // naming the scene, the largest file, the sizes and the flag.
  v1::SubmitJobResponse response;
  const grpc::Status large = farm.jobs().SubmitJob(
      FarmCluster::context().get(), submit_test_request(submit_test_noise_mesh(3'000'000, 3)),
      &response);
  EXPECT_EQ(large.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << large.error_message();
  EXPECT_TRUE(std::regex_search(
      large.error_message(),
      std::regex("^scene\\.xml: checking it needs [0-9]+ MiB \\(the most for mesh\\.serialized: "
                 "[0-9]+ MiB\\), more than the server's submit memory budget of 384 MiB \\(server "
                 "flag --submit-memory-mb\\)$")))
      << large.error_message();
}

}  // namespace
}  // namespace tessera::e2e
