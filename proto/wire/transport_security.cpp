#include "wire/transport_security.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tessera::wire {
namespace {

std::string trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t begin = s.find_first_not_of(ws);
  if (begin == std::string::npos) return {};
  return s.substr(begin, s.find_last_not_of(ws) - begin + 1);
}

void check_pair(const std::string& cert, const std::string& key, const char* cert_flag,
                const char* key_flag) {
  if (cert.empty() != key.empty()) {
    throw std::runtime_error(std::string(cert_flag) + " and " + key_flag +
                             " go together: give both or neither");
  }
}

}  // namespace

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": cannot read");
  return std::move(ss).str();
}

std::shared_ptr<grpc::ChannelCredentials> channel_credentials(const ClientTls& tls) {
  if (!tls.active()) return grpc::InsecureChannelCredentials();
  check_pair(tls.cert_file, tls.key_file, "--tls-cert", "--tls-key");
  grpc::SslCredentialsOptions options;
  if (!tls.ca_file.empty()) options.pem_root_certs = read_text_file(tls.ca_file);
  if (!tls.cert_file.empty()) {
    options.pem_cert_chain = read_text_file(tls.cert_file);
    options.pem_private_key = read_text_file(tls.key_file);
  }
  return grpc::SslCredentials(options);
}

std::shared_ptr<grpc::ServerCredentials> server_credentials(const ServerTls& tls) {
  check_pair(tls.cert_file, tls.key_file, "--tls-cert", "--tls-key");
  if (!tls.active()) {
    if (!tls.client_ca_file.empty()) {
      throw std::runtime_error(
          "--tls-client-ca needs --tls-cert and --tls-key (mutual TLS is TLS)");
    }
    return grpc::InsecureServerCredentials();
  }
  grpc::SslServerCredentialsOptions options(
      tls.client_ca_file.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                 : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  options.pem_key_cert_pairs.push_back(
      {read_text_file(tls.key_file), read_text_file(tls.cert_file)});
  if (!tls.client_ca_file.empty()) options.pem_root_certs = read_text_file(tls.client_ca_file);
  return grpc::SslServerCredentials(options);
}

std::string resolve_token(const std::string& token, const std::string& file,
                          const std::string& what) {
  if (file.empty()) return token;
  if (!token.empty()) {
    throw std::runtime_error(what + " and " + what + "-file both given: use one");
  }
  std::string content = read_text_file(file);
  std::string first = trim(content.substr(0, content.find('\n')));
  if (first.empty()) throw std::runtime_error(file + ": empty token (" + what + "-file)");
  return first;
}

bool is_loopback_address(const std::string& host_port) {
  if (host_port.starts_with("unix:")) return true;  // a local socket file
  std::string host = host_port;
  const size_t colon = host.rfind(':');
  if (host.starts_with('[')) {
    const size_t close = host.find(']');
    host = close == std::string::npos ? host : host.substr(1, close - 1);
  } else if (colon != std::string::npos && host.find(':') == colon) {
    host = host.substr(0, colon);  // "host:port"; a bare IPv6 address has several colons
  }
  if (host == "localhost" || host == "::1") return true;
  if (host.starts_with("127.")) {
    return host.find_first_not_of("0123456789.") == std::string::npos;
  }
  return false;
}

}  // namespace tessera::wire
