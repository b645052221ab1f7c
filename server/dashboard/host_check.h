// Which `Host` and `Origin` a dashboard request may name: the defence against DNS rebinding, where
// a page rebinds its own name to the dashboard's address and then calls it as its own origin
// (docs/security.md, "The dashboard"). Such a request names the attacker's host; a browser never
// lets a page forge either header.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tessera::server {

class HostCheck {
 public:
  /// `listen_host`: the host of the --http address; `allowed_names`: the --allowed-host names.
  /// Throws std::invalid_argument naming a value that is not a host name.
  HostCheck(std::string_view listen_host, const std::vector<std::string>& allowed_names);

  /// True when a `Host` header's host is an IP literal ("127.0.0.1", "[::1]"), "localhost", the
  /// listen host or an allowed name (any case, a trailing '.' ignored, any port). False for an
  /// empty or malformed value.
  bool allows_host(std::string_view host_header) const;
  /// True when an `Origin` "scheme://HOST[:PORT]" names a host that allows_host accepts; false
  /// for "null" and anything malformed.
  bool allows_origin(std::string_view origin) const;

  /// `name` in lower case without a trailing '.'; throws std::invalid_argument when it is not a
  /// host name (letters, digits, '-', '_', '.'; no scheme, port or path).
  static std::string normalise_name(std::string_view name);

 private:
  bool allows_name(std::string_view name) const;

  std::vector<std::string> names_;  ///< normalised: the listen host and the allowed names
};

}  // namespace tessera::server
