// `tessera delete JOB`: removes a finished, failed or cancelled job from the server (its record,
// output files and, when unused, its bundle; the database gives the space back). A queued or
// running job must be cancelled first; an unknown id exits 1 (docs/farm.md, "Deleting jobs").
#include <CLI/CLI.hpp>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_support.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "wire/rpc_channel.h"

namespace tessera::client {
namespace {

int delete_job(const GlobalOptions& g, uint64_t job_id) {
  const auto stub = v1::JobService::NewStub(wire::make_channel(g.server, g.tls));
  grpc::ClientContext context;
  wire::prepare_context(context, g.token, std::chrono::milliseconds(int64_t(g.timeout_s * 1000)));
  v1::DeleteJobRequest request;
  request.set_job_id(job_id);
  v1::DeleteJobResponse response;
  const grpc::Status status = stub->DeleteJob(&context, request, &response);
  if (!status.ok()) {
    const auto code = status.error_code();
    std::cerr << "tessera: "
              << (code == grpc::StatusCode::NOT_FOUND || code == grpc::StatusCode::FAILED_PRECONDITION
                      ? status.error_message()
                  : code == grpc::StatusCode::UNAVAILABLE
                      ? "cannot reach the server at " + g.server + " (" +
                            wire::status_line(status) + ")"
                      : wire::status_line(status))
              << "\n";
    return 1;
  }
  if (g.json) {
    std::cout << nlohmann::json{{"id", response.job_id()}, {"deleted", true}}.dump() << std::endl;
  } else {
    std::cout << "job " << response.job_id() << " deleted\n";
  }
  return 0;
}

}  // namespace

Command add_delete_command(CLI::App& app, GlobalOptions& g) {
  const auto job_id = std::make_shared<uint64_t>(0);
  CLI::App* cmd =
      app.add_subcommand("delete", "Delete a finished, failed or cancelled job and its outputs");
  add_job_argument(cmd, *job_id);
  add_json_flag(cmd, g);
  return {cmd, [&g, job_id] { return delete_job(g, *job_id); }};
}

}  // namespace tessera::client
