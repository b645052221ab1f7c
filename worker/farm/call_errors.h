// What a failed call to the server means to the farm worker: the exception each gRPC status
// becomes (a unit to hand back, a server to wait for, a token to fix, a registration to redo).
#pragma once

#include <grpcpp/support/status.h>

#include <stdexcept>

namespace tessera::farm {

/// A unit that cannot be rendered here (bad bundle, renderer error): handed back as failed.
class UnitFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The server cannot be reached or refuses us in a way retrying may fix.
class Transient : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Retrying cannot fix it (bad token): the worker exits 1.
class Fatal : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The server forgot this worker (a new database): register again.
class UnknownWorker : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

bool is_transient(grpc::StatusCode code);

/// Throws the exception the status calls for; returns on OK.
void check(const grpc::Status& status, const char* call);

}  // namespace tessera::farm
