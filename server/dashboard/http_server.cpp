#include "dashboard/http_server.h"

#include <openssl/ssl.h>

// Boost 1.74's Asio uses std::exchange without including <utility> (GCC 12 no longer brings it).
#include <utility>
// clang-format off: the include above must come first
#include <optional>
#include <stdexcept>
// clang-format on

#include "cli/host_port.h"
#include "dashboard/http_listener.h"

namespace tessera::server {
namespace {

/// The TLS context of --tls-cert/--tls-key; throws naming the files when they cannot be used.
asio::ssl::context make_tls_context(const std::string& cert_file, const std::string& key_file) {
  asio::ssl::context tls(asio::ssl::context::tls_server);
  tls.set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                  asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                  asio::ssl::context::no_tlsv1_1);
  beast::error_code ec;
  std::string why;
  if (cert_file.empty() || key_file.empty()) {
    why = "both are needed";
  } else if (tls.use_certificate_chain_file(cert_file, ec); ec) {
    why = "certificate: " + ec.message();
  } else if (tls.use_private_key_file(key_file, asio::ssl::context::pem, ec); ec) {
    why = "key: " + ec.message();
  } else if (SSL_CTX_check_private_key(tls.native_handle()) != 1) {
    why = "the key does not match the certificate";
  }
  if (!why.empty()) {
    throw std::runtime_error("HTTPS: cannot use certificate " + cert_file + " with key " +
                             key_file + " (--tls-cert, --tls-key): " + why);
  }
  return tls;
}

}  // namespace

DashboardServer::DashboardServer(Coordinator& coordinator, const FarmMetrics& metrics,
                                 DashboardConfig config)
    : coordinator_(coordinator), metrics_(metrics), config_(std::move(config)) {
  for (const std::string& name : config_.allowed_hosts) {
    try {
      HostCheck::normalise_name(name);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--allowed-host: ") + e.what());
    }
  }
  std::optional<asio::ssl::context> tls;
  if (!config_.tls_cert_file.empty() || !config_.tls_key_file.empty()) {
    tls.emplace(make_tls_context(config_.tls_cert_file, config_.tls_key_file));
  }
  listener_ = std::make_shared<Listener>(config_.limits, std::move(tls));
}

DashboardServer::~DashboardServer() { stop(); }

int DashboardServer::start(const std::string& address) {
  cli::HostPort hp;
  try {
    hp = cli::parse_host_port(address);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("--http: ") + e.what());
  }
  if (hp.unix_socket) throw std::runtime_error("--http: " + address + ": a unix: socket is gRPC only");
  DashboardRoutes routes(coordinator_, metrics_, config_,
                         HostCheck(hp.host, config_.allowed_hosts));
  tcp::endpoint endpoint;
  try {
    asio::io_context resolver_context;
    tcp::resolver resolver(resolver_context);
    const auto endpoints =
        resolver.resolve(hp.host, std::to_string(hp.port), tcp::resolver::passive);
    if (endpoints.empty()) throw std::runtime_error("no address");
    endpoint = endpoints.begin()->endpoint();
    return listener_->start(endpoint, std::move(routes));
  } catch (const boost::system::system_error&) {
    throw std::runtime_error("cannot listen on " + address + " (HTTP)");
  } catch (const std::runtime_error&) {
    throw std::runtime_error("cannot listen on " + address + " (HTTP)");
  }
}

void DashboardServer::stop() {
  if (listener_) listener_->stop();
}

}  // namespace tessera::server