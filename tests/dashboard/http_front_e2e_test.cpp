// The dashboard's HTTP front against a real tessera-server on loopback (label e2e): clients that
// never finish their request do not starve the health probes, a head that never ends is closed
// by its deadline, and a page that rebinds its DNS name to the server (a foreign Host or Origin)
// is refused. Every wait has a generous limit; nothing asserts how long anything took.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <tuple>

#include "farm_cluster.h"
#include "loopback_socket.h"

namespace tessera::e2e {
namespace {

const std::string kFrontTinyScene =
    (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();
constexpr auto kFrontPatience = std::chrono::seconds(30);

bool front_send(int fd, const std::string& text) {
  return ::send(fd, text.data(), text.size(), MSG_NOSIGNAL) == ssize_t(text.size());
}

/// True once the server has closed `fd` (end of stream or reset); false while it is open.
bool front_closed_by_server(int fd) {
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, 0) <= 0) return false;
  char buf[512];
  const ssize_t n = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
}

/// Sends a whole request on a fresh connection; returns the status of the answer and its body
/// (-1 when none came).
std::pair<int, std::string> front_exchange(int port, const std::string& request) {
  const int fd = connect_to_loopback(port);
  if (fd < 0) return {-1, ""};
  std::string got;
  if (front_send(fd, request)) {
    char buf[4096];
    for (;;) {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, size_t(n));
    }
  }
  ::close(fd);
  if (!got.starts_with("HTTP/1.") || got.size() < 12) return {-1, got};
  const size_t body = got.find("\r\n\r\n");
  return {std::stoi(got.substr(9, 3)), body == std::string::npos ? "" : got.substr(body + 4)};
}

std::string front_get(const std::string& path, const std::string& host,
                      const std::string& extra = "") {
  return "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\n" + extra + "\r\n";
}

std::string front_post(const std::string& path, const std::string& host, const std::string& origin,
                       const std::string& body) {
  std::string head = "POST " + path + " HTTP/1.1\r\nHost: " + host + "\r\n";
  if (!origin.empty()) head += "Origin: " + origin + "\r\n";
  return head + "Content-Type: application/json\r\nContent-Length: " +
         std::to_string(body.size()) + "\r\n\r\n" + body;
}

/// Connections that send a header line now and then and never finish their request.
class FrontSlowClients {
 public:
  FrontSlowClients(int port, int count) {
    for (int i = 0; i < count; ++i) {
      const int fd = connect_to_loopback(port);
      if (fd >= 0 && front_send(fd, "GET /api/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n")) {
        fds_.push_back(fd);
      } else if (fd >= 0) {
        ::close(fd);
      }
    }
    trickle_ = std::thread([this] {
      int line = 0;
      while (!stop_) {
        for (const int fd : fds_) front_send(fd, "X-Slow-" + std::to_string(line) + ": 1\r\n");
        ++line;
        for (int i = 0; i < 10 && !stop_; ++i) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
      }
    });
  }
  ~FrontSlowClients() {
    stop_ = true;
    trickle_.join();
    for (const int fd : fds_) ::close(fd);
  }
  size_t opened() const { return fds_.size(); }
  size_t closed_by_server() const {
    size_t closed = 0;
    for (const int fd : fds_) closed += front_closed_by_server(fd);
    return closed;
  }

 private:
  std::vector<int> fds_;
  std::atomic<bool> stop_{false};
  std::thread trickle_;
};

/// Polls `condition` every 100 ms until it holds or kFrontPatience passes; returns it.
template <typename F>
bool front_eventually(F condition) {
  const auto deadline = std::chrono::steady_clock::now() + kFrontPatience;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return true;
}

TEST(DashboardHttpFront, SlowClientsOfOneAddressNeverStarveTheProbes) {
  FarmCluster farm("dashboard-front-slow");
  // The cap from the environment (4 per client address); a head deadline long enough that only
  // the caps, not the deadline, close anything during the test.
  farm.set_server_env({"TESSERA_HTTP_CONNECTIONS_PER_CLIENT=4"});
  farm.start_server({"--http-head-timeout", "600"});
  const int port = farm.http_port();
  const std::string host = "127.0.0.1:" + std::to_string(port);

  // Far more than the cap and than any thread count of the server.
  constexpr int kSlow = 40;
  FrontSlowClients slow(port, kSlow);
  ASSERT_EQ(slow.opened(), size_t(kSlow));
  EXPECT_EQ(front_exchange(port, front_get("/healthz", host)).first, 200);
  EXPECT_EQ(front_exchange(port, front_get("/readyz", host)).first, 200);
  // Heads in progress are no request yet: the same address still gets its answers.
  const auto [jobs_status, jobs_body] = front_exchange(port, front_get("/api/jobs", host));
  EXPECT_EQ(jobs_status, 200) << jobs_body;
  // Each new connection from the address dropped its oldest unfinished one: at most 4 are left.
  EXPECT_TRUE(front_eventually([&] { return slow.closed_by_server() >= size_t(kSlow - 4); }))
      << slow.closed_by_server() << " of " << kSlow << " closed";

  // Requests past their head (a body that never comes) count against the cap: the fifth from
  // the address gets 503, the probes are still answered.
  const std::string never_ending_body =
      "POST /api/jobs/1/cancel HTTP/1.1\r\nHost: " + host +
      "\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{";
  std::vector<int> held;
  for (int i = 0; i < 4; ++i) {
    const int fd = connect_to_loopback(port);
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(front_send(fd, never_ending_body));
    held.push_back(fd);
  }
  std::pair<int, std::string> refused;
  EXPECT_TRUE(front_eventually([&] {
    refused = front_exchange(port, front_get("/api/jobs", host));
    return refused.first == 503;
  })) << refused.first << " " << refused.second;
  EXPECT_NE(refused.second.find("--http-connections-per-client"), std::string::npos)
      << refused.second;
  EXPECT_EQ(front_exchange(port, front_get("/healthz", host)).first, 200);
  EXPECT_EQ(front_exchange(port, front_get("/readyz", host)).first, 200);
  for (const int fd : held) ::close(fd);
  std::pair<int, std::string> again;
  EXPECT_TRUE(front_eventually([&] {
    again = front_exchange(port, front_get("/api/jobs", host));
    return again.first == 200;
  })) << again.first << " " << again.second;
  if (HasFailure()) farm.dump_logs();
}

TEST(DashboardHttpFront, AHeadThatNeverEndsIsClosedByItsDeadline) {
  FarmCluster farm("dashboard-front-deadline");
  farm.start_server({"--http-head-timeout", "1"});
  const int fd = connect_to_loopback(farm.http_port());
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(front_send(fd, "GET /api/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n"));
  // A header line every 200 ms: the deadline is on the whole head, not on a silence.
  int line = 0;
  const bool closed = front_eventually([&] {
    if (front_closed_by_server(fd)) return true;
    front_send(fd, "X-Line-" + std::to_string(line++) + ": 1\r\n");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return false;
  });
  ::close(fd);
  EXPECT_TRUE(closed) << "still open after " << line << " header lines";
  // The server goes on serving.
  EXPECT_EQ(front_exchange(farm.http_port(), front_get("/healthz", "127.0.0.1")).first, 200);
}

TEST(DashboardHttpFront, AForeignHostOrOriginIsRefusedSoDnsRebindingCannotCancelJobs) {
  FarmCluster farm("dashboard-front-host");
  farm.start_server({"--allowed-host", "dash.example.org", "--allowed-host", "proxy.example.org"});
  const int port = farm.http_port();
  const std::string p = ":" + std::to_string(port);
  const uint64_t id = farm.submit({kFrontTinyScene, "--spp", "64"});  // no worker: stays queued
  const std::string cancel = "/api/jobs/" + std::to_string(id) + "/cancel";

  // The attack: a page at attacker.example whose name now resolves to 127.0.0.1.
  auto [status, body] =
      front_exchange(port, front_post(cancel, "attacker.example" + p,
                                      "http://attacker.example" + p, "{}"));
  EXPECT_EQ(status, 403) << body;
  EXPECT_NE(body.find("attacker.example"), std::string::npos) << body;
  EXPECT_NE(body.find("--allowed-host"), std::string::npos) << body;
  // A POST from a foreign page through an accepted Host: its Origin gives it away.
  std::tie(status, body) =
      front_exchange(port, front_post(cancel, "127.0.0.1" + p, "http://attacker.example" + p, "{}"));
  EXPECT_EQ(status, 403) << body;
  EXPECT_NE(body.find("Origin"), std::string::npos) << body;
  std::tie(status, body) = front_exchange(port, front_post(cancel, "127.0.0.1" + p, "null", "{}"));
  EXPECT_EQ(status, 403) << body;
  EXPECT_EQ(farm.job(id).state(), v1::JOB_STATE_QUEUED);
  std::tie(status, body) = front_exchange(port, front_get("/api/jobs", "attacker.example" + p));
  EXPECT_EQ(status, 403) << body;
  std::tie(status, body) = front_exchange(port, front_get("/", "attacker.example"));
  EXPECT_EQ(status, 403) << body;

  // The server's own names.
  for (const std::string& host : std::vector<std::string>{"localhost" + p, "127.0.0.1" + p, "[::1]" + p,
                                  "dash.example.org" + p, "Proxy.Example.org", "localhost"}) {
    std::tie(status, body) = front_exchange(port, front_get("/api/jobs", host));
    EXPECT_EQ(status, 200) << host << ": " << body;
  }
  // The probes answer whatever the Host: they tell nothing and change nothing.
  EXPECT_EQ(front_exchange(port, front_get("/healthz", "attacker.example")).first, 200);
  EXPECT_EQ(front_exchange(port, front_get("/readyz", "attacker.example")).first, 200);

  // The page served through an allowed name changes jobs; so does a client sending no Origin.
  std::tie(status, body) = front_exchange(
      port, front_post("/api/jobs/" + std::to_string(id) + "/priority", "dash.example.org" + p,
                       "https://dash.example.org", R"({"priority": 3})"));
  EXPECT_EQ(status, 200) << body;
  EXPECT_EQ(farm.job(id).priority(), 3);
  std::tie(status, body) = front_exchange(port, front_post(cancel, "localhost" + p, "", "{}"));
  EXPECT_EQ(status, 200) << body;
  EXPECT_EQ(farm.job(id).state(), v1::JOB_STATE_CANCELLED);
  if (HasFailure()) farm.dump_logs();
}

TEST(DashboardHttpFront, TheHostIsCheckedWithATokenToo) {
  const std::string token = "front-secret";
  FarmCluster farm("dashboard-front-token");
  farm.start_server({"--token", token});
  const int port = farm.http_port();
  const std::string auth = "Authorization: Bearer " + token + "\r\n";
  auto [status, body] = front_exchange(port, front_get("/api/jobs", "attacker.example", auth));
  EXPECT_EQ(status, 403) << body;
  std::tie(status, body) = front_exchange(port, front_get("/api/jobs", "localhost", auth));
  EXPECT_EQ(status, 200) << body;
  std::tie(status, body) = front_exchange(port, front_get("/api/jobs", "localhost"));
  EXPECT_EQ(status, 401) << body;
}

TEST(DashboardHttpFront, ABadAllowedHostIsAUsageError) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-dashboard-front-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const CommandResult r =
      run_command({TESSERA_SERVER_BIN, "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0", "--db",
                   (dir / "bad.db").string(), "--allowed-host", "http://dash.example.org/"},
                  dir / "bad", {}, kPatience);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--allowed-host"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is not a host name"), std::string::npos) << r.err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera::e2e
