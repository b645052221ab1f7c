#include "call_errors.h"

#include <string>

#include "wire/rpc_channel.h"

namespace tessera::farm {

bool is_transient(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::CANCELLED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::ABORTED:
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::UNKNOWN:
      return true;
    default:
      return false;
  }
}

void check(const grpc::Status& status, const char* call) {
  if (status.ok()) return;
  const std::string line = std::string(call) + ": " + wire::status_line(status);
  switch (status.error_code()) {
    case grpc::StatusCode::UNAUTHENTICATED:
      // Say which token and where this worker reads it (docs/security.md, "Tokens and roles").
      throw Fatal(line +
                  "; the server wants its worker token (the server's --worker-token, or --token):"
                  " give it to this worker with --token or --token-file, or in TESSERA_TOKEN or"
                  " TESSERA_TOKEN_FILE");
    case grpc::StatusCode::PERMISSION_DENIED:
    case grpc::StatusCode::UNIMPLEMENTED:
      throw Fatal(line);
    default:
      break;
  }
  if (is_transient(status.error_code())) throw Transient(line);
  // The only FAILED_PRECONDITION of WorkerService: our worker id is unknown (worker_service.proto).
  if (status.error_code() == grpc::StatusCode::FAILED_PRECONDITION) throw UnknownWorker(line);
  throw UnitFailure(line);
}

}  // namespace tessera::farm
