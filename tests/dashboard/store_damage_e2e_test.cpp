// A damaged store is told everywhere an operator looks (label e2e): a real tessera-server,
// SIGKILLed, restarts on its store with the last pages overwritten; its background check finds
// the damage, and /api/store, the page's poll (/api/jobs), /metrics, /readyz, and `tessera
// status` and `tessera list` (one line on stderr) all say so.
#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "damaged_store.h"
#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

using nlohmann::json;

const std::string kTiny = (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

httplib::Result http_get(int port, const std::string& path) {
  httplib::Client c("127.0.0.1", port);
  c.set_read_timeout(60, 0);
  c.set_connection_timeout(10, 0);
  return c.Get(path.c_str());
}

json get_json(int port, const std::string& path) {
  httplib::Result r = http_get(port, path);
  if (!r) {
    ADD_FAILURE() << path << ": " << httplib::to_string(r.error());
    return {};
  }
  EXPECT_EQ(r->status, 200) << path << ": " << r->body;
  return json::parse(r->body);
}

size_t lines_of(const std::string& text) { return size_t(std::count(text.begin(), text.end(), '\n')); }

TEST(StoreDamage, IsToldByTheApiTheMetricsTheProbeAndTheCli) {
  FarmCluster farm("dashboard-store-damage");
  farm.start_server();
  const uint64_t id = farm.submit({kTiny, "--spp", "8"});  // no worker: it stays queued
  farm.kill_server();  // an unclean stop: the next start checks the whole file
  server::testing::fill_and_damage_store(farm.db_path());
  farm.start_server();
  const int port = farm.http_port();

  // The check runs beside the server: wait for its verdict (a poll, never a timing).
  json store;
  const auto give_up = std::chrono::steady_clock::now() + kPatience;
  for (;;) {
    store = get_json(port, "/api/store");
    if (store.value("state", "") == "damaged" || std::chrono::steady_clock::now() > give_up) break;
    ASSERT_TRUE(store.value("state", "") == "checking") << store;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(store["state"], "damaged") << store;
  EXPECT_EQ(store["check"], "damaged");
  EXPECT_FALSE(store["leasing"].get<bool>());
  const std::string damage = store["damage"];
  EXPECT_NE(damage.find("database " + farm.db_path().string() + " is damaged"), std::string::npos)
      << damage;
  EXPECT_NE(damage.find("quick_check"), std::string::npos) << damage;
  ASSERT_TRUE(store["check_progress"].is_number()) << store;

  // The job list carries it too (the page polls /api/store itself: it needs no query).
  EXPECT_EQ(get_json(port, "/api/jobs")["store"], store);

  // /metrics still answers though the workers' pages are garbage: the store's gauges need no
  // query, and the families a damaged store cannot give are left out.
  httplib::Result metrics = http_get(port, "/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200) << metrics->body;
  EXPECT_NE(metrics->body.find("\ntessera_store_damaged 1\n"), std::string::npos) << metrics->body;
  EXPECT_NE(metrics->body.find("\ntessera_store_check_running 0\n"), std::string::npos);
  httplib::Result ready = http_get(port, "/readyz");
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->status, 503) << ready->body;

  // The CLI: one line on stderr, the answer itself unchanged (exit 0, the job on stdout).
  const std::string warning = "tessera: warning: the server hands out no more work: database " +
                              farm.db_path().string() + " is damaged";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"list"}, {"status", std::to_string(id)},
        {"list", "--json"}}) {
    SCOPED_TRACE(args.front());
    const CommandResult r = farm.cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.rfind(warning, 0), 0u) << r.err;
    EXPECT_EQ(lines_of(r.err), 1u) << r.err;
    EXPECT_NE(r.out.find(std::to_string(id)), std::string::npos) << r.out;
  }
}

}  // namespace
}  // namespace tessera::e2e
