// Network addresses on the command line (`--grpc`, `--http`, `--server`): parsed once, so that a
// port out of range or a malformed address is refused by what is wrong instead of being wrapped
// or mistaken for a remote host (docs/security.md, "Listening beyond loopback").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace tessera::cli {

/// A parsed "HOST:PORT", "[IPV6]:PORT" or "unix:PATH".
struct HostPort {
  std::string host;  ///< name, IPv4 or IPv6 address (without brackets); the path for unix:
  int port = 0;      ///< in [0, 65535]; 0 asks a listener for any free port; -1 for unix:
  bool unix_socket = false;
};

/// Parses `address`. Throws std::invalid_argument naming what is wrong, e.g.
/// "127.0.0.1:99999: port 99999 is out of range [0, 65535]" or
/// "nonsense: expected HOST:PORT (no ':PORT')".
HostPort parse_host_port(const std::string& address);

/// A CLI11 check for a flag taking an address: the flag's value must parse with
/// parse_host_port (the error reads "--grpc: 127.0.0.1:99999: port 99999 is out of range ...").
CLI::Validator host_port_check();

}  // namespace tessera::cli
