#include "wire/bearer_token.h"

#include <openssl/crypto.h>

namespace tessera::wire {

BearerTokenCheck::BearerTokenCheck(std::string token)
    : expected_(token.empty() ? std::string() : "Bearer " + token) {}

grpc::Status BearerTokenCheck::check(const grpc::ServerContext& context) const {
  if (expected_.empty()) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end()) {
    return {grpc::StatusCode::UNAUTHENTICATED,
            "missing 'authorization: Bearer <token>' metadata (set --token or TESSERA_TOKEN)"};
  }
  const std::string_view got(it->second.data(), it->second.size());
  // Constant time over the expected length, so the comparison leaks nothing but the length.
  if (got.size() != expected_.size() ||
      CRYPTO_memcmp(got.data(), expected_.data(), expected_.size()) != 0) {
    return {grpc::StatusCode::UNAUTHENTICATED, "invalid token"};
  }
  return grpc::Status::OK;
}

}  // namespace tessera::wire
