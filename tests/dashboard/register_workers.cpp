// Registers N workers with a farm through the gRPC WorkerService, as real workers do at start,
// then exits: the browser test uses it to list 32 workers without running 32 renderers.
// Usage: tessera_register_workers HOST:PORT COUNT [TOKEN]
#include <iostream>
#include <string>

#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/rpc_channel.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: tessera_register_workers HOST:PORT COUNT [TOKEN]\n";
    return 2;
  }
  const std::string token = argc > 3 ? argv[3] : "";
  const int count = std::stoi(argv[2]);
  auto stub = tessera::v1::WorkerService::NewStub(tessera::wire::make_channel(argv[1]));
  for (int i = 0; i < count; ++i) {
    grpc::ClientContext context;
    tessera::wire::prepare_context(context, token, std::chrono::seconds(30));
    tessera::v1::RegisterRequest request;
    request.set_name("registered-" + std::to_string(i));
    request.set_threads(1 + i % 16);
    request.set_isa("avx2");
    request.set_version("test");
    tessera::v1::RegisterResponse response;
    const grpc::Status status = stub->Register(&context, request, &response);
    if (!status.ok()) {
      std::cerr << "tessera_register_workers: Register failed: " << status.error_message() << "\n";
      return 1;
    }
  }
  std::cout << count << " workers registered\n";
  return 0;
}
