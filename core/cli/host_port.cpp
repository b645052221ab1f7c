#include "cli/host_port.h"

#include <stdexcept>

namespace tessera::cli {
namespace {

[[noreturn]] void bad(const std::string& address, const std::string& why) {
  throw std::invalid_argument(address + ": " + why);
}

bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
         c == '.' || c == '_';
}

int parse_port(const std::string& address, const std::string& text) {
  if (text.empty()) bad(address, "the port is missing after ':'");
  if (text.find_first_not_of("0123456789") != std::string::npos) {
    bad(address, "port '" + text + "' is not a number in [0, 65535]");
  }
  // Digits only: compare by length first so that no conversion can overflow.
  const size_t first = text.find_first_not_of('0');
  const std::string digits = first == std::string::npos ? "0" : text.substr(first);
  if (digits.size() > 5 || std::stol(digits) > 65535) {
    bad(address, "port " + text + " is out of range [0, 65535]");
  }
  return int(std::stol(digits));
}

}  // namespace

HostPort parse_host_port(const std::string& address) {
  HostPort out;
  if (address.starts_with("unix:")) {
    out.unix_socket = true;
    out.port = -1;
    out.host = address.substr(5);
    if (out.host.empty()) bad(address, "the socket path is missing after 'unix:'");
    return out;
  }
  if (address.empty()) bad("''", "expected HOST:PORT (the address is empty)");
  size_t port_at = 0;
  if (address.starts_with('[')) {
    const size_t close = address.find(']');
    if (close == std::string::npos) bad(address, "'[' without its ']' around an IPv6 address");
    out.host = address.substr(1, close - 1);
    if (out.host.empty() || out.host.find_first_not_of(":.0123456789abcdefABCDEF") !=
                                std::string::npos || out.host.find(':') == std::string::npos) {
      bad(address, "'" + out.host + "' is not an IPv6 address");
    }
    if (close + 1 >= address.size() || address[close + 1] != ':') {
      bad(address, "expected [IPV6]:PORT (no ':PORT' after ']')");
    }
    port_at = close + 2;
  } else {
    const size_t colon = address.rfind(':');
    if (colon == std::string::npos) bad(address, "expected HOST:PORT (no ':PORT')");
    if (address.find(':') != colon) {
      bad(address, "an IPv6 address needs brackets: [ADDRESS]:PORT");
    }
    out.host = address.substr(0, colon);
    if (out.host.empty()) bad(address, "the host is missing before ':'");
    for (char c : out.host) {
      if (!is_name_char(c)) {
        bad(address, "'" + out.host + "' is not a host name or IP address");
      }
    }
    port_at = colon + 1;
  }
  out.port = parse_port(address, address.substr(port_at));
  return out;
}

CLI::Validator host_port_check() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        try {
          parse_host_port(value);
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
        return {};
      },
      "HOST:PORT");
}

}  // namespace tessera::cli
