// Transport security shared by every gRPC end of the farm (docs/security.md): TLS certificates
// for the server, the CA that clients trust, client certificates for mutual TLS, and tokens read
// from flags, environment variables or files.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace tessera::wire {

/// A client's side of TLS. Every path empty: plain TCP (insecure channel).
struct ClientTls {
  std::string
      ca_file;  ///< PEM CA bundle that signed the server's certificate; empty = system roots
  std::string cert_file;  ///< PEM client certificate (mutual TLS); needs key_file
  std::string key_file;   ///< PEM private key of cert_file
  /// Use TLS even with no file given (system roots). Set by any of the files above too.
  bool enabled = false;

  bool active() const { return enabled || !ca_file.empty() || !cert_file.empty(); }
};

/// The server's side of TLS. cert_file and key_file empty: plain TCP.
struct ServerTls {
  std::string cert_file;       ///< PEM certificate chain the server presents
  std::string key_file;        ///< PEM private key of cert_file
  std::string client_ca_file;  ///< non-empty: mutual TLS, every peer must present a certificate
                               ///< signed by this CA (verified by gRPC)

  bool active() const { return !cert_file.empty(); }
};

/// Throws std::runtime_error naming the file when one cannot be read or when only one of a
/// cert/key pair is given.
std::shared_ptr<grpc::ChannelCredentials> channel_credentials(const ClientTls& tls);
std::shared_ptr<grpc::ServerCredentials> server_credentials(const ServerTls& tls);

/// The whole content of a small text file (a PEM file, a token file). Throws std::runtime_error
/// "<path>: cannot read".
std::string read_text_file(const std::string& path);

/// A token given either directly or by file: returns `token` when `file` is empty, else the
/// file's first line with surrounding whitespace removed. Throws std::runtime_error when both
/// are given, or when the file cannot be read or holds an empty token. `what` names the flag in
/// messages ("--token").
std::string resolve_token(const std::string& token, const std::string& file,
                          const std::string& what);

/// True when HOST:PORT's host is a loopback address: "127.x.y.z", "localhost", "::1" (also in
/// brackets). "0.0.0.0", "[::]", host names and other addresses are not.
bool is_loopback_address(const std::string& host_port);

}  // namespace tessera::wire
