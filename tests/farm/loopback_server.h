// A gRPC server on 127.0.0.1 at a free port, for tests that run the farm's services in-process.
#pragma once

#include <grpcpp/grpcpp.h>

#include <initializer_list>
#include <memory>

namespace tessera::server::testing {

/// Serves `services` on 127.0.0.1 at a port the system picks, written to *port.
inline std::unique_ptr<grpc::Server> serve_on_loopback(std::initializer_list<grpc::Service*> services,
                                                       int* port) {
  grpc::ServerBuilder builder;
  builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), port);
  for (grpc::Service* service : services) builder.RegisterService(service);
  return builder.BuildAndStart();
}

}  // namespace tessera::server::testing
