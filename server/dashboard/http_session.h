// One connection of the dashboard's listener: its request read, checked, answered and closed
// (HttpSession, plain or TLS, in http_session.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "dashboard/http_listener.h"

namespace tessera::server {

/// The session of a new connection of `listener`: HTTPS through `tls` when not null, plain
/// HTTP otherwise. Not started: the caller registers it, then calls run().
std::shared_ptr<HttpSessionBase> make_http_session(DashboardServer::Listener& listener,
                                                  tcp::socket socket, asio::ssl::context* tls,
                                                  const std::string& address, uint64_t id);

}  // namespace tessera::server
