// SubmitBudget: reservations against the capacity, waiting first come first served, refusals
// naming the flag; submit_check_cost from the files' headers.
#include "submit_budget.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <future>
#include <thread>

#include "farm_error.h"

namespace tessera::server {
namespace {

using std::chrono::milliseconds;

constexpr milliseconds kBudgetTestPatience{60'000};

/// Polls `done` until it holds, failing after kBudgetTestPatience.
template <typename Done>
void budget_test_wait_until(Done done) {
  const auto give_up = std::chrono::steady_clock::now() + kBudgetTestPatience;
  while (!done()) {
    ASSERT_LT(std::chrono::steady_clock::now(), give_up) << "condition never held";
    std::this_thread::sleep_for(milliseconds(2));
  }
}

FarmError budget_test_error(SubmitBudget& budget, uint64_t bytes, milliseconds wait) {
  try {
    budget.reserve(bytes, "scene.xml", "", wait);
  } catch (const FarmError& e) {
    return e;
  }
  return FarmError(ErrorCode::internal, "(no error)");
}

TEST(SubmitBudget, ReservesUpToItsCapacityAndReleasesOnDestruction) {
  SubmitBudget budget(100);
  {
    SubmitBudget::Reservation a = budget.reserve(60, "a.json", "", milliseconds(0));
    SubmitBudget::Reservation b = budget.reserve(40, "b.json", "", milliseconds(0));
    EXPECT_EQ(budget.counters().reserved_bytes, 100u);
  }
  const SubmitBudget::Counters c = budget.counters();
  EXPECT_EQ(c.reserved_bytes, 0u);
  EXPECT_EQ(c.peak_reserved_bytes, 100u);
  EXPECT_EQ(c.admitted, 2u);
  EXPECT_EQ(c.waited, 0u);
  EXPECT_EQ(c.capacity_bytes, 100u);
}

TEST(SubmitBudget, RefusesMoreThanTheCapacityNamingSizeAndFlag) {
  SubmitBudget budget(uint64_t(64) << 20);
  try {
    budget.reserve(uint64_t(700) << 20, "scene.xml", "the most for mesh.serialized: 690 MiB",
                   milliseconds(0));
    FAIL() << "no error";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_EQ(std::string(e.what()),
              "scene.xml: checking it needs 700 MiB (the most for mesh.serialized: 690 MiB), more "
              "than the server's submit memory budget of 64 MiB (server flag --submit-memory-mb)");
  }
  EXPECT_EQ(budget.counters().refused_too_large, 1u);
  EXPECT_EQ(budget.counters().admitted, 0u);
}

TEST(SubmitBudget, AWaitThatEndsFirstIsResourceExhaustedNamingTheFlag) {
  SubmitBudget budget(100);
  SubmitBudget::Reservation held = budget.reserve(80, "a.json", "", milliseconds(0));
  const FarmError e = budget_test_error(budget, 30, milliseconds(0));
  EXPECT_EQ(e.code(), ErrorCode::resource_exhausted) << e.what();
  EXPECT_NE(std::string(e.what()).find("(server flag --submit-memory-mb)"), std::string::npos)
      << e.what();
  EXPECT_EQ(budget.counters().refused_busy, 1u);
  EXPECT_EQ(budget.counters().waiting, 0u);
  EXPECT_EQ(budget.counters().reserved_bytes, 80u);
}

TEST(SubmitBudget, WaitersAreAdmittedFirstComeFirstServedAsMemoryIsReleased) {
  SubmitBudget budget(100);
  std::optional<SubmitBudget::Reservation> held(budget.reserve(60, "a.json", "", milliseconds(0)));
  // b does not fit beside a; c would, but asked after b.
  auto b = std::async(std::launch::async, [&] {
    return budget.reserve(60, "b.json", "", kBudgetTestPatience).bytes();
  });
  budget_test_wait_until([&] { return budget.counters().waiting == 1; });
  auto c = std::async(std::launch::async, [&] {
    return budget.reserve(10, "c.json", "", kBudgetTestPatience).bytes();
  });
  budget_test_wait_until([&] { return budget.counters().waiting == 2; });
  EXPECT_EQ(budget.counters().admitted, 1u);
  held.reset();
  EXPECT_EQ(b.get(), 60u);
  EXPECT_EQ(c.get(), 10u);
  const SubmitBudget::Counters counters = budget.counters();
  EXPECT_EQ(counters.admitted, 3u);
  EXPECT_EQ(counters.waited, 2u);
  EXPECT_LE(counters.peak_reserved_bytes, 100u);
  EXPECT_EQ(counters.reserved_bytes, 0u);
}

/// A serialized file of one float shape declaring `vertices` and `triangles`, whose stream holds
/// `payload` (compressed as it is).
std::string budget_test_serialized(uint64_t vertices, uint64_t triangles,
                                   const std::string& payload) {
  std::string body(4, '\0');
  const uint32_t flags = 0x1000;
  std::memcpy(body.data(), &flags, 4);
  body += "s";
  body += '\0';
  body.append(reinterpret_cast<const char*>(&vertices), 8);
  body.append(reinterpret_cast<const char*>(&triangles), 8);
  body += payload;
  uLongf size = compressBound(body.size());
  std::string out(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                      reinterpret_cast<const Bytef*>(body.data()), body.size(), 9),
            Z_OK);
  out.resize(size);
  return std::string("\x1c\x04\x04\x00", 4) + out;
}

TEST(SubmitCheckCost, CountsTheBundleThriceAndEachMeshFromItsHeader) {
  v1::SceneBundle bundle;
  bundle.set_scene_file("scene.xml");
  auto* scene = bundle.add_files();
  scene->set_path("scene.xml");
  scene->set_data("<scene version=\"3.0.0\"/>");
  // 1000 vertices and 2000 triangles of pseudo-random bytes (they do not compress):
  // 1000 x 24 + 2000 x 12 bytes loaded, counted three times.
  std::string payload(1000 * 12 + 2000 * 12, '\0');
  uint32_t x = 12345;
  for (char& c : payload) c = char((x = x * 1664525u + 1013904223u) >> 24);
  auto* mesh = bundle.add_files();
  mesh->set_path("meshes/a.serialized");
  mesh->set_data(budget_test_serialized(1000, 2000, payload));
  uint64_t bundle_bytes = scene->data().size() + mesh->data().size();
  SubmitCost cost = submit_check_cost(bundle, 1000);
  EXPECT_EQ(cost.bytes, 3 * bundle_bytes + 3 * (1000 * 24 + 2000 * 12));
  EXPECT_EQ(cost.largest_file, "meshes/a.serialized");
  // A bomb (20M zero vertices and triangles): refused from its header, so it costs only its
  // bytes.
  auto* bomb = bundle.add_files();
  bomb->set_path("meshes/bomb.serialized");
  bomb->set_data(budget_test_serialized(20'000'000, 20'000'000, std::string(24 << 20, '\0')));
  bundle_bytes += bomb->data().size();
  cost = submit_check_cost(bundle, 1000);
  EXPECT_EQ(cost.bytes, 3 * bundle_bytes + 3 * (1000 * 24 + 2000 * 12));
}

}  // namespace
}  // namespace tessera::server
