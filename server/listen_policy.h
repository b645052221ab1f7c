// The start-up rule that keeps an unauthenticated service off the network (docs/security.md,
// "Listening beyond loopback"). One function for every listener: gRPC now, HTTP too.
#pragma once

#include <string>

namespace tessera::server {

/// `address` is where a listener binds ("HOST:PORT"); `unauthenticated` names what it would
/// serve without a token ("clients (JobService)"), empty when everything needs one. Throws
/// std::runtime_error with a one-line reason when the address is not loopback and something is
/// unauthenticated, unless `insecure`. Returns a warning line to log ("" when none): --insecure
/// used, or tokens sent in clear (no `tls`) beyond loopback.
std::string check_listen_policy(const std::string& address, const std::string& unauthenticated,
                                bool tls, bool insecure);

}  // namespace tessera::server
