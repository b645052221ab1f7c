// Every RPC of both services refuses a missing or wrong token. The methods are enumerated from
// the generated service descriptors, so a new RPC cannot be forgotten: if its handler skips the
// token check, this test fails for it by name.
#include <google/protobuf/descriptor.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "coordinator.h"
#include "fake_clock.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "job_service.h"
#include "listen_policy.h"
#include "wire/rpc_channel.h"
#include "wire/transport_security.h"
#include "worker_service.h"

namespace tessera::server {
namespace {

constexpr const char* kClientToken = "client-secret";
constexpr const char* kWorkerToken = "worker-secret";

/// Both services on 127.0.0.1 (a free port) over a :memory: store, with separate tokens.
class AuthServer {
 public:
  AuthServer() : coordinator_(config(), clock_) {
    grpc::EnableDefaultHealthCheckService(true);
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
    builder.RegisterService(&jobs_);
    builder.RegisterService(&workers_);
    server_ = builder.BuildAndStart();
  }
  ~AuthServer() {
    coordinator_.stop_leasing();
    server_->Shutdown(std::chrono::system_clock::now());
  }

  std::shared_ptr<grpc::Channel> channel() const {
    return wire::make_channel("127.0.0.1:" + std::to_string(port_));
  }

 private:
  static CoordinatorConfig config() {
    CoordinatorConfig c;
    c.db_path = ":memory:";
    c.output_dir = std::filesystem::temp_directory_path() / "tessera-auth-test-outputs";
    return c;
  }

  testing::FakeClock clock_;
  Coordinator coordinator_;
  wire::BearerTokenCheck client_auth_{kClientToken};
  wire::BearerTokenCheck worker_auth_{kWorkerToken};
  JobServiceImpl jobs_{coordinator_, client_auth_};
  WorkerServiceImpl workers_{coordinator_, worker_auth_};
  int port_ = 0;
  std::unique_ptr<grpc::Server> server_;
};

/// Calls `method` ("/pkg.Service/Method") with an empty request through the generic stub (works
/// for unary and streaming methods alike) and returns the final status.
grpc::Status call(grpc::GenericStub& stub, const std::string& method, const std::string& token) {
  grpc::ClientContext context;
  wire::prepare_context(context, token, std::chrono::seconds(30));
  grpc::CompletionQueue cq;
  auto next = [&cq] {
    void* tag = nullptr;
    bool ok = false;
    EXPECT_TRUE(cq.Next(&tag, &ok));
    return ok;
  };
  std::unique_ptr<grpc::GenericClientAsyncReaderWriter> rpc =
      stub.PrepareCall(&context, method, &cq);
  rpc->StartCall(reinterpret_cast<void*>(1));
  grpc::Status status;
  if (next()) {
    grpc::ByteBuffer empty;
    grpc::Slice slice("", 0);
    empty = grpc::ByteBuffer(&slice, 1);
    rpc->Write(empty, reinterpret_cast<void*>(2));
    if (next()) {
      rpc->WritesDone(reinterpret_cast<void*>(3));
      next();
      // Drain the responses (Finish waits for them to be read).
      grpc::ByteBuffer response;
      do {
        rpc->Read(&response, reinterpret_cast<void*>(5));
      } while (next());
    }
  }
  rpc->Finish(&status, reinterpret_cast<void*>(4));
  next();
  return status;
}

std::vector<std::string> methods_of(const std::string& service_name) {
  const auto* service =
      google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(service_name);
  EXPECT_NE(service, nullptr) << service_name;
  std::vector<std::string> out;
  for (int i = 0; service && i < service->method_count(); ++i) {
    out.push_back("/" + service_name + "/" + service->method(i)->name());
  }
  return out;
}

struct ServiceCase {
  std::string service;
  std::string right_token, other_role_token;
};

TEST(Auth, EveryMethodOfBothServicesRefusesMissingAndWrongTokens) {
  // Make sure the generated code (and so its descriptors) is linked in.
  ASSERT_NE(v1::JobService::service_full_name(), nullptr);
  ASSERT_NE(v1::WorkerService::service_full_name(), nullptr);
  AuthServer server;
  grpc::GenericStub stub(server.channel());
  const std::vector<ServiceCase> cases = {{"tessera.v1.JobService", kClientToken, kWorkerToken},
                                          {"tessera.v1.WorkerService", kWorkerToken, kClientToken}};
  int methods = 0;
  for (const ServiceCase& c : cases) {
    for (const std::string& method : methods_of(c.service)) {
      ++methods;
      for (const std::string& bad : {std::string(), std::string("wrong"), c.other_role_token,
                                     c.right_token + "x", c.right_token.substr(1)}) {
        const grpc::Status status = call(stub, method, bad);
        EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED)
            << method << " with token \"" << bad << "\": " << wire::status_line(status);
      }
      // With its role's token the call gets past authentication (it may fail on the empty
      // request, with another code).
      const grpc::Status status = call(stub, method, c.right_token);
      EXPECT_NE(status.error_code(), grpc::StatusCode::UNAUTHENTICATED)
          << method << ": " << wire::status_line(status);
      EXPECT_NE(status.error_code(), grpc::StatusCode::UNIMPLEMENTED) << method;
    }
  }
  EXPECT_GE(methods, 13);  // 7 JobService + 6 WorkerService today; more is fine
}

TEST(Auth, HealthServiceAnswersWithoutAToken) {
  // The documented choice (docs/security.md): orchestrators probe health without secrets; it
  // reveals only SERVING / NOT_SERVING.
  AuthServer server;
  auto health = grpc::health::v1::Health::NewStub(server.channel());
  grpc::ClientContext context;
  wire::prepare_context(context, "", std::chrono::seconds(30));
  grpc::health::v1::HealthCheckResponse response;
  ASSERT_TRUE(health->Check(&context, {}, &response).ok());
  EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING);
}

TEST(TransportSecurity, LoopbackAddresses) {
  for (const char* a : {"127.0.0.1:50051", "127.0.0.1:0", "127.1.2.3:9", "localhost:50051",
                        "[::1]:50051", "unix:/tmp/tessera.sock"}) {
    EXPECT_TRUE(wire::is_loopback_address(a)) << a;
  }
  for (const char* a : {"0.0.0.0:50051", "[::]:50051", "10.0.0.7:50051", "farm.example:50051",
                        "127.0.0.1.example.com:1", "128.0.0.1:1", ":50051"}) {
    EXPECT_FALSE(wire::is_loopback_address(a)) << a;
  }
}

TEST(TransportSecurity, ListenPolicy) {
  // Loopback: anything goes, silently.
  EXPECT_EQ(check_listen_policy("127.0.0.1:50051", "clients (JobService)", false, false), "");
  // Beyond loopback: refused while something is unauthenticated...
  try {
    check_listen_policy("0.0.0.0:8080", "the dashboard", false, false);
    ADD_FAILURE() << "not refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("refusing to listen on non-loopback address 0.0.0.0:8080"
                                         " with no token for the dashboard"),
              std::string::npos)
        << e.what();
  }
  // ...unless --insecure (a warning), and warned about plain TCP when tokens are set.
  EXPECT_NE(check_listen_policy("0.0.0.0:1", "x", false, true).find("WITHOUT authentication"),
            std::string::npos);
  EXPECT_NE(check_listen_policy("10.0.0.7:1", "", false, false).find("without TLS"),
            std::string::npos);
  EXPECT_EQ(check_listen_policy("10.0.0.7:1", "", true, false), "");
}

TEST(TransportSecurity, TokensFromFiles) {
  const auto path =
      std::filesystem::temp_directory_path() / ("tessera-token-" + std::to_string(::getpid()));
  { std::ofstream(path) << "  s3cret \nsecond line ignored\n"; }
  EXPECT_EQ(wire::resolve_token("", path.string(), "--token"), "s3cret");
  EXPECT_EQ(wire::resolve_token("direct", "", "--token"), "direct");
  EXPECT_THROW(wire::resolve_token("direct", path.string(), "--token"), std::runtime_error);
  EXPECT_THROW(wire::resolve_token("", (path.string() + ".missing"), "--token"),
               std::runtime_error);
  { std::ofstream(path) << "\n"; }
  EXPECT_THROW(wire::resolve_token("", path.string(), "--token"), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(TransportSecurity, CertificateFlagsGoInPairs) {
  wire::ServerTls server;
  server.cert_file = "server.crt";
  EXPECT_THROW(wire::server_credentials(server), std::runtime_error);
  wire::ServerTls mtls_without_tls;
  mtls_without_tls.client_ca_file = "ca.crt";
  EXPECT_THROW(wire::server_credentials(mtls_without_tls), std::runtime_error);
  wire::ClientTls client;
  client.cert_file = "client.crt";
  EXPECT_THROW(wire::channel_credentials(client), std::runtime_error);
  wire::ClientTls missing_ca;
  missing_ca.ca_file = "/nonexistent/ca.crt";
  EXPECT_THROW(wire::channel_credentials(missing_ca), std::runtime_error);
}

}  // namespace
}  // namespace tessera::server
