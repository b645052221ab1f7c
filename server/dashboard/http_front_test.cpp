// The dashboard's HTTP front without sockets: which Host and Origin a request may name (DNS
// rebinding), how the connection table admits, refuses and drops connections per client
// address, and the request target's decoding.
#include <gtest/gtest.h>

#include <stdexcept>

#include "dashboard/connection_table.h"
#include "dashboard/host_check.h"
#include "dashboard/http_message.h"

namespace tessera::server {
namespace {

using Admission = ConnectionTable::Admission;

TEST(HttpFrontHostCheck, AcceptsIpLiteralsLocalhostTheListenHostAndAllowedNames) {
  const HostCheck check("render-box", {"Dash.Example.org", "ingress.local."});
  for (const char* host : {"127.0.0.1", "127.0.0.1:8080", "10.1.2.3:80", "[::1]", "[::1]:8080",
                           "[fe80::1]:1", "localhost", "LOCALHOST:8080", "localhost.:1",
                           "render-box:8080", "dash.example.org", "DASH.EXAMPLE.ORG:443",
                           "dash.example.org.", "ingress.local:8080"}) {
    EXPECT_TRUE(check.allows_host(host)) << host;
  }
}

TEST(HttpFrontHostCheck, RefusesOtherNamesAndMalformedHosts) {
  const HostCheck check("127.0.0.1", {"dash.example.org"});
  for (const char* host : {"attacker.example", "attacker.example:8080", "example.org",
                           "evil.dash.example.org", "dash.example.org.evil", "localhost.evil",
                           "", ":8080", "::1", "[::1", "[::1]x", "[nope]:80", "127.0.0.1:port",
                           "127.0.0.1:123456", "2130706433", "a b"}) {
    EXPECT_FALSE(check.allows_host(host)) << host;
  }
}

TEST(HttpFrontHostCheck, OriginsAreJudgedByTheirHost) {
  const HostCheck check("127.0.0.1", {"dash.example.org"});
  for (const char* origin : {"http://127.0.0.1:8080", "https://localhost", "http://[::1]:9",
                             "https://dash.example.org"}) {
    EXPECT_TRUE(check.allows_origin(origin)) << origin;
  }
  for (const char* origin : {"null", "", "http://attacker.example:8080", "attacker.example",
                             "http://127.0.0.1/path", "http://user@127.0.0.1",
                             "://127.0.0.1"}) {
    EXPECT_FALSE(check.allows_origin(origin)) << origin;
  }
}

TEST(HttpFrontHostCheck, AnAllowedHostMustBeAName) {
  EXPECT_EQ(HostCheck::normalise_name("Dash.Example.ORG."), "dash.example.org");
  for (const char* bad : {"", "http://dash.example.org", "dash.example.org:8080", "a/b", "a b"}) {
    try {
      HostCheck::normalise_name(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("is not a host name"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(HostCheck("127.0.0.1", {"x/y"}), std::invalid_argument);
}

TEST(HttpFrontConnectionTable, ANewConnectionDropsTheOldestHeadOfItsAddressOnly) {
  ConnectionTable table(/*per_client=*/3, /*max_total=*/100);
  std::vector<uint64_t> slow;
  for (int i = 0; i < 3; ++i) {
    const ConnectionTable::Opened opened = table.open("10.0.0.1");
    ASSERT_NE(opened.id, 0u);
    EXPECT_TRUE(opened.drop.empty());
    slow.push_back(opened.id);
  }
  const ConnectionTable::Opened other = table.open("10.0.0.2");
  EXPECT_TRUE(other.drop.empty());
  const ConnectionTable::Opened fourth = table.open("10.0.0.1");
  ASSERT_EQ(fourth.drop.size(), 1u);
  EXPECT_EQ(fourth.drop[0], slow[0]);
  EXPECT_EQ(table.connections(), 4u);  // 3 of 10.0.0.1 (the dropped one gone), 1 of 10.0.0.2
  table.close(slow[0]);                // the dropped connection closing later changes nothing
  EXPECT_EQ(table.connections(), 4u);
  // The newest connection (a probe) is read, and is served whatever the others hold.
  EXPECT_EQ(table.head_done(fourth.id, /*exempt=*/true), Admission::exempt);
  EXPECT_EQ(table.heads(), (std::vector<uint64_t>{slow[1], slow[2], other.id}));
}

TEST(HttpFrontConnectionTable, RequestsPastTheirHeadAreCappedPerAddressButProbesAreNot) {
  ConnectionTable table(/*per_client=*/2, /*max_total=*/100);
  std::vector<uint64_t> admitted;
  for (int i = 0; i < 2; ++i) {
    const uint64_t id = table.open("10.0.0.1").id;
    ASSERT_EQ(table.head_done(id, false), Admission::admitted);
    admitted.push_back(id);
  }
  const uint64_t refused = table.open("10.0.0.1").id;
  EXPECT_EQ(table.head_done(refused, false), Admission::client_full);
  const uint64_t probe = table.open("10.0.0.1").id;
  EXPECT_EQ(table.head_done(probe, true), Admission::exempt);
  const uint64_t elsewhere = table.open("10.0.0.2").id;
  EXPECT_EQ(table.head_done(elsewhere, false), Admission::admitted);
  EXPECT_EQ(table.admitted(), 3u);
  table.close(admitted[0]);
  const uint64_t again = table.open("10.0.0.1").id;
  EXPECT_EQ(table.head_done(again, false), Admission::admitted);
  for (const uint64_t id : {admitted[1], refused, probe, elsewhere, again}) table.close(id);
  EXPECT_EQ(table.connections(), 0u);
  EXPECT_EQ(table.admitted(), 0u);
}

TEST(HttpFrontConnectionTable, TheTotalCapDropsTheOldestHeadAndKeepsAReserveForHeads) {
  // 16 in all: at most 14 past their head (an eighth, 2, kept for heads and probes).
  ConnectionTable table(/*per_client=*/100, /*max_total=*/16);
  std::vector<uint64_t> admitted;
  for (int i = 0; i < 14; ++i) {
    const uint64_t id = table.open("10.0.1." + std::to_string(i)).id;
    ASSERT_EQ(table.head_done(id, false), Admission::admitted) << i;
    admitted.push_back(id);
  }
  const uint64_t over = table.open("10.0.2.1").id;
  EXPECT_EQ(table.head_done(over, false), Admission::server_full);
  table.close(over);
  const uint64_t head_a = table.open("10.0.3.1").id;
  const uint64_t head_b = table.open("10.0.3.2").id;
  EXPECT_EQ(table.connections(), 16u);
  // Full: a new connection takes the oldest head's place, of whichever address.
  const ConnectionTable::Opened probe = table.open("10.0.4.1");
  ASSERT_NE(probe.id, 0u);
  EXPECT_EQ(probe.drop, (std::vector<uint64_t>{head_a}));
  EXPECT_EQ(table.head_done(probe.id, true), Admission::exempt);
  // With no head left to drop, a new connection is refused.
  const ConnectionTable::Opened next = table.open("10.0.4.2");
  ASSERT_NE(next.id, 0u);
  EXPECT_EQ(next.drop, (std::vector<uint64_t>{head_b}));
  EXPECT_EQ(table.head_done(next.id, true), Admission::exempt);
  EXPECT_EQ(table.open("10.0.4.3").id, 0u);
  EXPECT_EQ(table.connections(), 16u);
}

TEST(HttpFrontMessage, TargetsAreSplitAndDecodedLikeAnyServerDoes) {
  std::string path;
  HttpFields params;
  split_target("/api/jobs%2F7?limit=5&name=a+b%21&flag&=x", path, params);
  EXPECT_EQ(path, "/api/jobs/7");
  const HttpFields expected = {{"limit", "5"}, {"name", "a b!"}, {"flag", ""}, {"", "x"}};
  EXPECT_EQ(params, expected);
  split_target("/a+b%zz%4", path, params);
  EXPECT_EQ(path, "/a+b%zz%4");  // '+' is a space only in the query; bad escapes stay
  EXPECT_TRUE(params.empty());

  HttpRequest req;
  req.headers = {{"Content-Type", "application/json"}, {"content-type", "text/plain"}};
  req.params = {{"limit", "3"}};
  EXPECT_EQ(req.header("CONTENT-TYPE"), "application/json");
  EXPECT_FALSE(req.has_header("Content-Length"));
  EXPECT_EQ(req.param("limit"), "3");
  EXPECT_FALSE(req.has_param("Limit"));
  HttpResponse res;
  res.set_header("Cache-Control", "no-cache");
  res.set_header("cache-control", "no-store");
  EXPECT_EQ(res.headers, (HttpFields{{"cache-control", "no-store"}}));
}

}  // namespace
}  // namespace tessera::server
