// Security end to end (docs/security.md): TLS and mutual TLS with throwaway certificates made by
// `openssl` at test time (no key is ever committed), role tokens and token files, the refusal to
// listen beyond loopback without a token, the client refusing symbolic links, and a graceful
// SIGTERM that leaves a checkpointed, intact database. Everything connects to 127.0.0.1 only.
#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <thread>
#include <nlohmann/json.hpp>

#include "farm_cluster.h"
#include "store/integrity.h"
#include "store/sqlite.h"

namespace tessera::e2e {
namespace {

const std::string kTiny = (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

/// A CA, a server certificate for 127.0.0.1, and a client certificate, all from the CA.
struct Certificates {
  std::filesystem::path ca, server_cert, server_key, client_cert, client_key, rogue_cert, rogue_key;
};

void run_openssl(const std::filesystem::path& dir, const std::vector<std::string>& args,
                 int& step) {
  std::vector<std::string> argv = {"/usr/bin/openssl"};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandResult r =
      run_command(argv, dir / ("openssl-" + std::to_string(step++)), {}, std::chrono::minutes(2));
  ASSERT_EQ(r.exit_code, 0) << "openssl " << args.front() << ": " << r.err;
}

Certificates make_certificates(const std::filesystem::path& dir) {
  Certificates c;
  const auto p = [&](const std::string& name) { return dir / name; };
  c.ca = p("ca.crt");
  c.server_cert = p("server.crt");
  c.server_key = p("server.key");
  c.client_cert = p("client.crt");
  c.client_key = p("client.key");
  c.rogue_cert = p("rogue.crt");
  c.rogue_key = p("rogue.key");
  std::ofstream(p("server.ext")) << "subjectAltName=IP:127.0.0.1,DNS:localhost\n";
  int step = 0;
  const std::vector<std::string> ec = {"-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
                                       "-nodes"};
  auto with = [&](std::vector<std::string> head, const std::vector<std::string>& tail) {
    head.insert(head.end(), tail.begin(), tail.end());
    return head;
  };
  run_openssl(dir,
              with(with({"req", "-x509"}, ec), {"-keyout", p("ca.key"), "-out", c.ca, "-days", "1",
                                                "-subj", "/CN=tessera-test-ca"}),
              step);
  run_openssl(dir,
              with(with({"req"}, ec),
                   {"-keyout", c.server_key, "-out", p("server.csr"), "-subj", "/CN=127.0.0.1"}),
              step);
  run_openssl(dir,
              {"x509", "-req", "-in", p("server.csr"), "-CA", c.ca, "-CAkey", p("ca.key"),
               "-CAcreateserial", "-out", c.server_cert, "-days", "1", "-extfile", p("server.ext")},
              step);
  run_openssl(dir,
              with(with({"req"}, ec), {"-keyout", c.client_key, "-out", p("client.csr"), "-subj",
                                       "/CN=tessera-worker"}),
              step);
  run_openssl(dir,
              {"x509", "-req", "-in", p("client.csr"), "-CA", c.ca, "-CAkey", p("ca.key"),
               "-CAcreateserial", "-out", c.client_cert, "-days", "1"},
              step);
  // A self-signed certificate the server's CA never signed.
  run_openssl(dir,
              with(with({"req", "-x509"}, ec), {"-keyout", c.rogue_key, "-out", c.rogue_cert,
                                                "-days", "1", "-subj", "/CN=rogue"}),
              step);
  return c;
}

std::vector<std::string> strings(std::initializer_list<std::filesystem::path> paths) {
  std::vector<std::string> out;
  for (const auto& p : paths) out.push_back(p.string());
  return out;
}

void expect_tiny_job_renders(FarmCluster& farm, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {
      "submit", kTiny, "--spp", "4", "--json", "-o", (farm.dir() / "tiny.png").string()};
  const CommandResult r = farm.cli(args, extra);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json job = nlohmann::json::parse(r.out);
  EXPECT_EQ(job["state"], "done") << r.out;
  EXPECT_TRUE(std::filesystem::exists(farm.dir() / "tiny.png"));
}

TEST(SecurityE2E, TlsServerWorkerAndCliRenderAJob) {
  FarmCluster farm("tls");
  const Certificates c = make_certificates(farm.dir());
  wire::ClientTls tls;
  tls.ca_file = c.ca.string();
  farm.use_tls(tls, {"--tls-ca", c.ca.string()});
  farm.start_server({"--tls-cert", c.server_cert.string(), "--tls-key", c.server_key.string(),
                     "--token", "tls-token"});
  farm.start_worker({"--tls-ca", c.ca.string(), "--token", "tls-token"});
  expect_tiny_job_renders(farm);
  // A plain-TCP client cannot talk to a TLS server; one that does not trust the CA neither.
  const CommandResult plain = run_command({TESSERA_CLI_BIN, "--server", farm.address(), "--token",
                                           "tls-token", "--timeout", "10", "list"},
                                          farm.dir() / "plain");
  EXPECT_EQ(plain.exit_code, 1);
  const CommandResult untrusted =
      run_command({TESSERA_CLI_BIN, "--server", farm.address(), "--tls-ca", c.rogue_cert.string(),
                   "--token", "tls-token", "--timeout", "10", "list"},
                  farm.dir() / "untrusted");
  EXPECT_EQ(untrusted.exit_code, 1);
  // The dashboard serves HTTPS with the same certificate; a client trusting the CA gets an
  // answer, one speaking plain HTTP does not.
  httplib::SSLClient https("127.0.0.1", farm.http_port());
  https.set_ca_cert_path(c.ca.string().c_str());
  https.enable_server_certificate_verification(true);
  https.set_connection_timeout(10, 0);
  const httplib::Result health = https.Get("/healthz");
  ASSERT_TRUE(health) << "HTTPS /healthz: " << httplib::to_string(health.error());
  EXPECT_EQ(health->status, 200);
  httplib::Client plain_http("127.0.0.1", farm.http_port());
  plain_http.set_connection_timeout(10, 0);
  plain_http.set_read_timeout(10, 0);
  const httplib::Result plain_health = plain_http.Get("/healthz");
  EXPECT_TRUE(!plain_health || plain_health->status != 200);
}

TEST(SecurityE2E, MutualTlsAdmitsOnlyPeersWithACertificateFromTheCa) {
  FarmCluster farm("mtls");
  const Certificates c = make_certificates(farm.dir());
  wire::ClientTls tls;
  tls.ca_file = c.ca.string();
  tls.cert_file = c.client_cert.string();
  tls.key_file = c.client_key.string();
  farm.use_tls(tls, {"--tls-ca", c.ca.string(), "--tls-cert", c.client_cert.string(), "--tls-key",
                     c.client_key.string()});
  farm.start_server({"--tls-cert", c.server_cert.string(), "--tls-key", c.server_key.string(),
                     "--tls-client-ca", c.ca.string()});
  farm.start_worker(
      strings({"--tls-ca", c.ca, "--tls-cert", c.client_cert, "--tls-key", c.client_key}));
  expect_tiny_job_renders(farm);
  // Without a client certificate, or with one the CA did not sign: refused.
  for (const auto& extra : {std::vector<std::string>{},
                            strings({"--tls-cert", c.rogue_cert, "--tls-key", c.rogue_key})}) {
    std::vector<std::string> argv = {
        TESSERA_CLI_BIN, "--server", farm.address(), "--tls-ca", c.ca.string(), "--timeout", "10"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    argv.push_back("list");
    const CommandResult r =
        run_command(argv, farm.dir() / ("no-cert-" + std::to_string(extra.size())));
    EXPECT_EQ(r.exit_code, 1) << r.out;
  }
}

TEST(SecurityE2E, WorkerAndClientTokensAreSeparateRolesAndReadFromFiles) {
  FarmCluster farm("roles");
  std::ofstream(farm.dir() / "worker.token") << "worker-role-token\n";
  farm.start_server({"--client-token", "client-role-token", "--worker-token-file",
                     (farm.dir() / "worker.token").string()});
  // The client token does not open the worker service: that worker gives up (exit 1).
  const size_t wrong = farm.start_worker({"--token", "client-role-token"});
  EXPECT_EQ(farm.worker(wrong).wait_for(kPatience), 1);
  // It says which token it needs and where it reads one.
  const std::string log = read_text(farm.dir() / ("worker-" + std::to_string(wrong) + ".log"));
  EXPECT_NE(log.find("the server wants its worker token"), std::string::npos) << log;
  EXPECT_NE(log.find("--token-file"), std::string::npos) << log;
  // The worker token does not open the job service.
  const CommandResult refused = farm.cli({"list"}, {"TESSERA_TOKEN=worker-role-token"});
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("UNAUTHENTICATED"), std::string::npos) << refused.err;
  farm.start_worker({"--token-file", (farm.dir() / "worker.token").string()});
  expect_tiny_job_renders(farm);  // the cluster passes the client token
}

TEST(SecurityE2E, NonLoopbackWithoutATokenIsRefusedAtStartUp) {
  FarmCluster farm("listen");
  const CommandResult r = run_command(
      {TESSERA_SERVER_BIN, "--grpc", "0.0.0.0:0", "--db", (farm.dir() / "farm.db").string()},
      farm.dir() / "server");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("refusing to listen on non-loopback address 0.0.0.0:0"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--insecure"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // A role without its token is refused the same way.
  const CommandResult half =
      run_command({TESSERA_SERVER_BIN, "--grpc", "[::]:0", "--client-token", "only-clients", "--db",
                   (farm.dir() / "farm.db").string()},
                  farm.dir() / "server-half");
  EXPECT_EQ(half.exit_code, 1);
  EXPECT_NE(half.err.find("workers (WorkerService)"), std::string::npos) << half.err;
}

TEST(SecurityE2E, ServerLimitFlagsRefuseJobsWithTheirReason) {
  FarmCluster farm("limits");
  farm.start_server({"--max-spp", "16", "--max-queued-jobs", "1"});
  const CommandResult spp = farm.cli({"submit", kTiny, "--spp", "17"});
  EXPECT_EQ(spp.exit_code, 1);
  EXPECT_NE(spp.err.find("--spp: must be in [1, 16] (got 17)"), std::string::npos) << spp.err;
  EXPECT_EQ(std::count(spp.err.begin(), spp.err.end(), '\n'), 1) << spp.err;
  ASSERT_NE(farm.submit({kTiny, "--spp", "16"}), 0u);  // no worker: it stays queued
  const CommandResult quota = farm.cli({"submit", kTiny, "--spp", "4"});
  EXPECT_EQ(quota.exit_code, 1);
  EXPECT_NE(quota.err.find("RESOURCE_EXHAUSTED"), std::string::npos) << quota.err;
  EXPECT_NE(quota.err.find("--max-queued-jobs"), std::string::npos) << quota.err;
}

TEST(SecurityE2E, ClientRefusesToBundleSymbolicLinks) {
  FarmCluster farm("symlinks");
  farm.start_server();
  const auto scenes = farm.dir() / "scenes";
  std::filesystem::create_directories(scenes / "meshes");
  std::filesystem::copy_file(kTiny, scenes / "real.json");
  std::filesystem::create_symlink(scenes / "real.json", scenes / "linked.json");
  const CommandResult linked = farm.cli({"submit", (scenes / "linked.json").string()});
  EXPECT_EQ(linked.exit_code, 1);
  EXPECT_NE(linked.err.find("symbolic link"), std::string::npos) << linked.err;
  // A mesh reached through a link (here to a file outside the scene's folder) is refused too.
  std::ofstream(farm.dir() / "outside.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::filesystem::create_symlink(farm.dir() / "outside.obj", scenes / "meshes" / "m.obj");
  std::ofstream(scenes / "mesh.json")
      << R"({"tessera": 1, "camera": {"position": [0,0,3], "look_at": [0,0,0], "fov": 40},
             "film": {"width": 8, "height": 8},
             "materials": {"white": {"type": "diffuse", "reflectance": [0.5,0.5,0.5]}},
             "shapes": [{"type": "mesh", "file": "meshes/m.obj", "material": "white"},
                        {"type": "quad", "vertices": [[-1,2,-1],[1,2,-1],[1,2,1],[-1,2,1]],
                         "emission": [5,5,5]}]})";
  const CommandResult mesh = farm.cli({"submit", (scenes / "mesh.json").string()});
  EXPECT_EQ(mesh.exit_code, 1);
  EXPECT_NE(mesh.err.find("symbolic links are not allowed"), std::string::npos) << mesh.err;
  const CommandResult list = farm.cli({"list", "--json"});
  EXPECT_TRUE(nlohmann::json::parse(list.out).empty()) << list.out;
}

TEST(SecurityE2E, SigtermStopsLeasingCommitsAndLeavesACheckpointedIntactDatabase) {
  FarmCluster farm("sigterm");
  farm.start_server();
  farm.start_worker();
  expect_tiny_job_renders(farm);
  EXPECT_EQ(farm.stop_server(SIGTERM), 0);
  const auto wal = farm.db_path().string() + "-wal";
  EXPECT_TRUE(!std::filesystem::exists(wal) || std::filesystem::file_size(wal) == 0);
  server::Database db(farm.db_path().string());
  EXPECT_NO_THROW(server::check_integrity(db, farm.db_path().string()));
  auto q = db.prepare("SELECT state FROM jobs");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->text(0), "done");
}

TEST(SecurityE2E, ADamagedDatabaseIsRefusedAtStartUp) {
  FarmCluster farm("damaged");
  const auto db = farm.dir() / "farm.db";
  std::ofstream(db, std::ios::binary) << std::string(8192, '\x42');  // not a database at all
  const CommandResult r = run_command(
      {TESSERA_SERVER_BIN, "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0", "--db", db.string()}, farm.dir() / "server");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is damaged"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("refusing to serve it"), std::string::npos) << r.err;
}

// Damage where start-up does not read, after an unclean stop: the server listens at once, its
// background check finds the damage, says so in its log and answers /readyz 503 (that it then
// leases nothing is StoreIntegrity.DamageFoundByTheBackgroundCheckStopsLeasingAndIsReported);
// stopped with SIGTERM it leaves no clean mark, so the next start checks again.
TEST(SecurityE2E, DamageFoundByTheBackgroundCheckIsReportedWhileServing) {
  FarmCluster farm("damaged-late");
  farm.start_server();
  ASSERT_EQ(farm.stop_server(SIGTERM), 0);
  int64_t page = 0;
  {
    server::Database db(farm.db_path().string());
    server::Transaction t(db);
    for (int i = 0; i < 3000; ++i) {
      db.exec(
          "INSERT INTO workers (name, threads, isa, version, registered_unix_ms,"
          " last_seen_unix_ms) VALUES ('worker with a long name to fill pages', 1, 'avx2',"
          " '0', 0, 0)");
    }
    t.commit();
    db.exec("PRAGMA user_version = 0");  // as a SIGKILL leaves it: no clean-shutdown mark
    ASSERT_TRUE(server::checkpoint_wal(db));
    auto q = db.prepare("PRAGMA page_size");
    ASSERT_TRUE(q->step());
    page = q->int64(0);
  }
  const auto size = std::filesystem::file_size(farm.db_path());
  ASSERT_GT(size, uint64_t(page) * 40);
  {
    // The last 8 pages (leaves of the workers table, written last) overwritten with garbage.
    std::fstream file(farm.db_path(), std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(size - uint64_t(page) * 8));
    const std::string garbage(size_t(page) * 8, '\x5a');
    file.write(garbage.data(), std::streamsize(garbage.size()));
  }
  farm.start_server();  // fails the test if the server exits instead of listening
  httplib::Client http("127.0.0.1", farm.http_port());
  http.set_connection_timeout(10, 0);
  http.set_read_timeout(10, 0);
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    const httplib::Result ready = http.Get("/readyz");
    ASSERT_TRUE(ready) << "/readyz: " << httplib::to_string(ready.error());
    status = ready->status;
    if (status == 503) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(status, 503);
  EXPECT_EQ(farm.stop_server(SIGTERM), 0);
  std::ifstream log(farm.dir() / "server-1.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("checking it (PRAGMA quick_check) in the background"), std::string::npos)
      << text;
  EXPECT_NE(text.find("ERROR: database " + farm.db_path().string() + " is damaged"),
            std::string::npos)
      << text;
  server::Database db(farm.db_path().string());
  EXPECT_FALSE(server::take_clean_shutdown_mark(db, farm.db_path().string()));
}

}  // namespace
}  // namespace tessera::e2e
