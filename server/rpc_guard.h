// The common frame of every RPC handler: check the bearer token, run the handler, and turn the
// farm's exceptions into gRPC statuses with one-line messages.
#pragma once

#include <grpcpp/grpcpp.h>

#include <exception>
#include <iostream>

#include "farm_error.h"
#include "store/sqlite.h"
#include "wire/bearer_token.h"

namespace tessera::server {

inline grpc::StatusCode to_grpc(ErrorCode code) {
  switch (code) {
    case ErrorCode::invalid_argument: return grpc::StatusCode::INVALID_ARGUMENT;
    case ErrorCode::not_found: return grpc::StatusCode::NOT_FOUND;
    case ErrorCode::failed_precondition: return grpc::StatusCode::FAILED_PRECONDITION;
    case ErrorCode::resource_exhausted: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case ErrorCode::internal: return grpc::StatusCode::INTERNAL;
  }
  return grpc::StatusCode::INTERNAL;
}

/// Runs `handler` (returning grpc::Status) after the token check; exceptions become statuses:
/// FarmError by its code, SQLite busy/locked as UNAVAILABLE (retryable), anything else INTERNAL
/// (and logged on stderr: it is a bug or a broken disk).
template <typename Handler>
grpc::Status guarded(const wire::BearerTokenCheck& auth, const grpc::ServerContext& context,
                     const char* method, Handler&& handler) {
  if (grpc::Status status = auth.check(context); !status.ok()) return status;
  try {
    return handler();
  } catch (const FarmError& e) {
    return {to_grpc(e.code()), e.what()};
  } catch (const SqliteError& e) {
    if (e.primary_code() == SQLITE_BUSY || e.primary_code() == SQLITE_LOCKED) {
      return {grpc::StatusCode::UNAVAILABLE, std::string("store busy: ") + e.what()};
    }
    std::cerr << "tessera-server: " << method << ": store error: " << e.what() << "\n";
    return {grpc::StatusCode::INTERNAL, std::string("store error: ") + e.what()};
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << method << ": " << e.what() << "\n";
    return {grpc::StatusCode::INTERNAL, e.what()};
  }
}

}  // namespace tessera::server
