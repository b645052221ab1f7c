#include "cli/host_port.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace tessera::cli {
namespace {

std::string host_port_error(const std::string& address) {
  try {
    parse_host_port(address);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(HostPort, ParsesNamesIpv4Ipv6AndUnixSockets) {
  EXPECT_EQ(parse_host_port("127.0.0.1:50051").host, "127.0.0.1");
  EXPECT_EQ(parse_host_port("127.0.0.1:50051").port, 50051);
  EXPECT_EQ(parse_host_port("localhost:0").port, 0);
  EXPECT_EQ(parse_host_port("render-01.farm.example:65535").port, 65535);
  EXPECT_EQ(parse_host_port("[::1]:8080").host, "::1");
  EXPECT_EQ(parse_host_port("[::1]:8080").port, 8080);
  EXPECT_TRUE(parse_host_port("unix:/run/tessera.sock").unix_socket);
}

// Before: 127.0.0.1:99999 listened on 34463 (99999 mod 65536) and "nonsense" was taken for a
// remote host.
TEST(HostPort, RefusesPortsOutOfRangeAndMalformedAddressesByWhatIsWrong) {
  EXPECT_EQ(host_port_error("127.0.0.1:99999"), "127.0.0.1:99999: port 99999 is out of range [0, 65535]");
  EXPECT_EQ(host_port_error("127.0.0.1:65536"), "127.0.0.1:65536: port 65536 is out of range [0, 65535]");
  EXPECT_EQ(host_port_error("127.0.0.1:99999999999999999999999"),
            "127.0.0.1:99999999999999999999999: port 99999999999999999999999 is out of range "
            "[0, 65535]");
  EXPECT_EQ(host_port_error("127.0.0.1:-1"), "127.0.0.1:-1: port '-1' is not a number in [0, 65535]");
  EXPECT_EQ(host_port_error("nonsense"), "nonsense: expected HOST:PORT (no ':PORT')");
  EXPECT_EQ(host_port_error("127.0.0.1:"), "127.0.0.1:: the port is missing after ':'");
  EXPECT_EQ(host_port_error(":50051"), ":50051: the host is missing before ':'");
  EXPECT_EQ(host_port_error("bad host:1"), "bad host:1: 'bad host' is not a host name or IP address");
  EXPECT_EQ(host_port_error("::1:80"), "::1:80: an IPv6 address needs brackets: [ADDRESS]:PORT");
  EXPECT_EQ(host_port_error("[::1"), "[::1: '[' without its ']' around an IPv6 address");
  EXPECT_EQ(host_port_error("[::1]"), "[::1]: expected [IPV6]:PORT (no ':PORT' after ']')");
  EXPECT_EQ(host_port_error("[zz]:1"), "[zz]:1: 'zz' is not an IPv6 address");
  EXPECT_EQ(host_port_error("unix:"), "unix:: the socket path is missing after 'unix:'");
  EXPECT_EQ(host_port_error(""), "'': expected HOST:PORT (the address is empty)");
}

}  // namespace
}  // namespace tessera::cli
