// The farm's shared-secret authentication: when the server has a token, every call must carry
// `authorization: Bearer <token>`. (Issue "auth" replaces this with per-user credentials; this is
// the simple but real version: constant-time comparison, no token in logs.)
#pragma once

#include <grpcpp/grpcpp.h>

#include <string>

namespace tessera::wire {

class BearerTokenCheck {
 public:
  /// An empty token accepts every call.
  explicit BearerTokenCheck(std::string token);

  /// OK, or UNAUTHENTICATED saying what is missing or wrong (never the expected token).
  grpc::Status check(const grpc::ServerContext& context) const;

  bool enabled() const { return !expected_.empty(); }

 private:
  std::string expected_;  ///< "Bearer <token>", or empty
};

}  // namespace tessera::wire
