// The flags with which a client of the farm (the `tessera` CLI, a farm worker) authenticates and
// secures its channel: one definition, so both take the same names and environment variables
// (docs/security.md).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "wire/transport_security.h"

namespace tessera::wire {

/// --token/--token-file (TESSERA_TOKEN, TESSERA_TOKEN_FILE) and --tls, --tls-ca, --tls-cert,
/// --tls-key (TESSERA_TLS...). `token_help` says whose token it is; `cert_help` whose
/// certificate --tls-cert is. resolve_token() turns token and token_file into the token sent.
inline void add_client_auth_flags(CLI::App& app, std::string& token, std::string& token_file,
                                  ClientTls& tls, const std::string& token_help,
                                  const std::string& cert_help) {
  app.add_option("--token", token, token_help)->envname("TESSERA_TOKEN");
  app.add_option("--token-file", token_file, "Read the access token from this file (first line)")
      ->envname("TESSERA_TOKEN_FILE");
  app.add_option("--tls-ca", tls.ca_file,
                 "Use TLS; trust server certificates signed by this CA (PEM)")
      ->envname("TESSERA_TLS_CA");
  app.add_flag("--tls", tls.enabled, "Use TLS with the system's trusted CAs")
      ->envname("TESSERA_TLS");
  app.add_option("--tls-cert", tls.cert_file, cert_help)->envname("TESSERA_TLS_CERT");
  app.add_option("--tls-key", tls.key_file, "Private key (PEM) of --tls-cert")
      ->envname("TESSERA_TLS_KEY");
}

}  // namespace tessera::wire
