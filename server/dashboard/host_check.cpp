#include "dashboard/host_check.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace tessera::server {
namespace {

bool host_check_is_ipv4(const std::string& text) {
  in_addr a{};
  return inet_pton(AF_INET, text.c_str(), &a) == 1;
}

bool host_check_is_ipv6(const std::string& text) {
  in6_addr a{};
  return inet_pton(AF_INET6, text.c_str(), &a) == 1;
}

bool host_check_is_port(std::string_view text) {
  return !text.empty() && text.size() <= 5 &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::string host_check_lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (!out.empty() && out.back() == '.') out.pop_back();
  return out;
}

}  // namespace

std::string HostCheck::normalise_name(std::string_view name) {
  std::string lower = host_check_lower(name);
  const bool valid = !lower.empty() && lower.size() <= 253 &&
                     std::all_of(lower.begin(), lower.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || c == '-' ||
                              c == '_' || c == '.';
                     });
  if (!valid) {
    throw std::invalid_argument("\"" + std::string(name) +
                                "\" is not a host name (letters, digits, '-', '_' and '.'; no "
                                "scheme, port or path)");
  }
  return lower;
}

HostCheck::HostCheck(std::string_view listen_host, const std::vector<std::string>& allowed_names) {
  // The listen host may be an IP literal (accepted anyway) or a name, taken as given.
  if (!listen_host.empty()) names_.push_back(host_check_lower(listen_host));
  for (const std::string& name : allowed_names) names_.push_back(normalise_name(name));
}

bool HostCheck::allows_name(std::string_view name) const {
  const std::string lower = host_check_lower(name);
  if (lower.empty()) return false;
  if (lower == "localhost" || host_check_is_ipv4(lower)) return true;
  return std::find(names_.begin(), names_.end(), lower) != names_.end();
}

bool HostCheck::allows_host(std::string_view host) const {
  if (host.empty()) return false;
  if (host.front() == '[') {  // "[IPV6]" or "[IPV6]:PORT"
    const size_t close = host.find(']');
    if (close == std::string_view::npos) return false;
    const std::string_view rest = host.substr(close + 1);
    if (!rest.empty() && !(rest.front() == ':' && host_check_is_port(rest.substr(1)))) {
      return false;
    }
    return host_check_is_ipv6(std::string(host.substr(1, close - 1)));
  }
  const size_t colon = host.find(':');
  if (colon != std::string_view::npos) {
    // One ':' only, followed by a port: an unbracketed IPv6 address is not a valid Host.
    if (!host_check_is_port(host.substr(colon + 1))) return false;
    host = host.substr(0, colon);
  }
  return allows_name(host);
}

bool HostCheck::allows_origin(std::string_view origin) const {
  const size_t scheme_end = origin.find("://");
  if (scheme_end == std::string_view::npos || scheme_end == 0) return false;  // "null" too
  const std::string_view host = origin.substr(scheme_end + 3);
  // An origin is scheme, host and port: no path, no user information.
  if (host.find_first_of("/@?#") != std::string_view::npos) return false;
  return allows_host(host);
}

}  // namespace tessera::server
