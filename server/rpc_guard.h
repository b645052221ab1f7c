// The common frame of every RPC handler: check the bearer token, run the handler, and turn the
// farm's exceptions into gRPC statuses with one-line messages.
#pragma once

#include <grpcpp/grpcpp.h>

#include <exception>
#include <iostream>
#include <utility>

#include "farm_error.h"
#include "scene/message_text.h"
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

/// Runs `handler` (returning grpc::Status); exceptions become statuses: FarmError by its code,
/// SQLite busy/locked as UNAVAILABLE (retryable), anything else INTERNAL (and logged on stderr:
/// it is a bug or a broken disk).
template <typename Handler>
grpc::Status status_of(const char* method, Handler&& handler) {
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

/// The most bytes of a status message the server sends (before escaping). gRPC carries the
/// message in a trailer under an 8 KiB limit: a longer one is replaced by a transport error and
/// its reason is lost.
inline constexpr size_t kStatusMessageBytes = 2048;

/// `status` with its message one line (control characters, NUL included, as \xNN) and at most
/// kStatusMessageBytes long, whatever input it quotes.
inline grpc::Status bounded(const grpc::Status& status) {
  if (status.ok()) return status;
  return {status.error_code(), printable(status.error_message(), kStatusMessageBytes),
          status.error_details()};
}

/// Runs `handler` after the token check, as status_of(), and bounds() its status.
template <typename Handler>
grpc::Status guarded(const wire::BearerTokenCheck& auth, const grpc::ServerContext& context,
                     const char* method, Handler&& handler) {
  if (grpc::Status status = auth.check(context); !status.ok()) return status;
  return bounded(status_of(method, std::forward<Handler>(handler)));
}

}  // namespace tessera::server
