#include "listen_policy.h"

#include <stdexcept>

#include "wire/transport_security.h"

namespace tessera::server {

std::string check_listen_policy(const std::string& address, const std::string& unauthenticated,
                                bool tls, bool insecure) {
  if (wire::is_loopback_address(address)) return {};
  if (unauthenticated.empty()) {
    if (tls) return {};
    return "listening on " + address +
           " without TLS: tokens and scenes cross the network in clear (see --tls-cert)";
  }
  if (!insecure) {
    throw std::runtime_error("refusing to listen on non-loopback address " + address +
                             " with no token for " + unauthenticated +
                             ": set --token (or --token-file, TESSERA_TOKEN), or pass --insecure"
                             " to serve anyone who can reach it");
  }
  return "--insecure: serving " + unauthenticated + " on " + address + " WITHOUT authentication";
}

}  // namespace tessera::server
