#include "farm_cluster.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "wire/rpc_channel.h"

namespace tessera::e2e {
namespace {

void poll_pause() { std::this_thread::sleep_for(std::chrono::milliseconds(25)); }

}  // namespace

std::filesystem::path source_dir() { return TESSERA_SOURCE_DIR; }

FarmCluster::FarmCluster(const std::string& name) {
  dir_ = std::filesystem::temp_directory_path() /
         ("tessera-e2e-" + name + "-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

FarmCluster::~FarmCluster() {
  const bool failed = ::testing::Test::HasFailure();
  if (failed) dump_logs();
  workers_.clear();  // SIGKILL and reap
  server_.reset();
  if (!failed) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
}

void FarmCluster::start_server(const std::vector<std::string>& extra) {
  if (!extra.empty() || server_starts_ == 0) server_extra_ = extra;
  for (size_t i = 0; i + 1 < server_extra_.size(); ++i) {
    if (server_extra_[i] == "--token" || server_extra_[i] == "--client-token") {
      token_ = server_extra_[i + 1];
    }
  }
  const auto port_file = dir_ / "port";
  std::filesystem::remove(port_file);
  std::vector<std::string> argv = {TESSERA_SERVER_BIN,
                                   "--grpc",
                                   "127.0.0.1:" + std::to_string(port_),
                                   "--db",
                                   db_path().string(),
                                   "--output-dir",
                                   (dir_ / "outputs").string(),
                                   "--port-file",
                                   port_file.string(),
                                   "--http",
                                   "127.0.0.1:0",
                                   "--http-port-file",
                                   (dir_ / "http-port").string()};
  argv.insert(argv.end(), server_extra_.begin(), server_extra_.end());
  server_ = std::make_unique<Process>(
      argv, dir_ / ("server-" + std::to_string(server_starts_++) + ".log"), server_env_);
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (!std::filesystem::exists(port_file)) {
    if (!server_->running()) FAIL() << "tessera-server exited at start";
    if (std::chrono::steady_clock::now() > deadline) FAIL() << "tessera-server did not start";
    poll_pause();
  }
  port_ = std::stoi(read_text(port_file));
  http_port_ = std::stoi(read_text(dir_ / "http-port"));  // written before the gRPC one
  connect();
}

void FarmCluster::connect() {
  auto channel = wire::make_channel(address(), tls_);
  jobs_ = v1::JobService::NewStub(channel);
  workers_api_ = v1::WorkerService::NewStub(channel);
}

std::optional<int> FarmCluster::stop_server(int signal_number) {
  server_->signal(signal_number);
  return server_->wait_for(kPatience);
}

void FarmCluster::kill_server() {
  server_->signal(SIGKILL);
  ASSERT_TRUE(server_->wait_for(kPatience).has_value());
}

size_t FarmCluster::start_worker(const std::vector<std::string>& extra,
                                 const std::vector<std::string>& env) {
  const size_t index = workers_.size();
  std::vector<std::string> argv = {TESSERA_WORKER_BIN, "--server", address(), "--cache",
                                   (dir_ / "cache").string(), "--name",
                                   "e2e-worker-" + std::to_string(index)};
  argv.insert(argv.end(), extra.begin(), extra.end());
  workers_.push_back(
      std::make_unique<Process>(argv, dir_ / ("worker-" + std::to_string(index) + ".log"), env));
  return index;
}

CommandResult FarmCluster::cli(const std::vector<std::string>& args,
                               const std::vector<std::string>& env) {
  std::vector<std::string> argv = {TESSERA_CLI_BIN, "--server", address()};
  argv.insert(argv.end(), cli_tls_flags_.begin(), cli_tls_flags_.end());
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<std::string> child_env = env;
  bool has_token = false;
  for (const std::string& e : env) has_token = has_token || e.rfind("TESSERA_TOKEN=", 0) == 0;
  if (!has_token && !token_.empty()) child_env.push_back("TESSERA_TOKEN=" + token_);
  return run_command(argv, dir_ / ("cli-" + std::to_string(commands_++)), child_env, kPatience);
}

CommandResult FarmCluster::local_render(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {TESSERA_WORKER_BIN, "render"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, dir_ / ("render-" + std::to_string(commands_++)), {}, kPatience);
}

std::unique_ptr<grpc::ClientContext> FarmCluster::context(const std::string& token) {
  auto context = std::make_unique<grpc::ClientContext>();
  wire::prepare_context(*context, token, kCallTimeout);
  return context;
}

v1::JobInfo FarmCluster::job(uint64_t id) {
  v1::GetJobRequest request;
  request.set_job_id(id);
  v1::JobInfo info;
  // The server may be restarting: retry transient failures within the patience.
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  for (;;) {
    auto ctx = context(token_);
    const grpc::Status status = jobs_->GetJob(ctx.get(), request, &info);
    if (status.ok()) return info;
    if (status.error_code() != grpc::StatusCode::UNAVAILABLE ||
        std::chrono::steady_clock::now() > deadline) {
      ADD_FAILURE() << "GetJob " << id << ": " << wire::status_line(status);
      return info;
    }
    poll_pause();
  }
}

v1::JobInfo FarmCluster::wait_job(uint64_t id, const std::function<bool(const v1::JobInfo&)>& done,
                                  const std::string& what) {
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  for (;;) {
    const v1::JobInfo info = job(id);
    if (done(info) || ::testing::Test::HasFailure()) return info;
    if (std::chrono::steady_clock::now() > deadline) {
      ADD_FAILURE() << "job " << id << ": gave up waiting for " << what << "; last state "
                    << info.ShortDebugString();
      return info;
    }
    poll_pause();
  }
}

v1::JobInfo FarmCluster::wait_final(uint64_t id) {
  return wait_job(
      id,
      [](const v1::JobInfo& j) {
        return j.state() == v1::JOB_STATE_DONE || j.state() == v1::JOB_STATE_FAILED ||
               j.state() == v1::JOB_STATE_CANCELLED;
      },
      "a final state");
}

uint64_t FarmCluster::submit(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"submit"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back("--json");
  const CommandResult r = cli(argv);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return 0;
  return nlohmann::json::parse(r.out).at("id").get<uint64_t>();
}

void FarmCluster::dump_logs() const {
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".log" || entry.path().extension() == ".err") {
      std::cerr << "----- " << name << "\n" << read_text(entry.path()) << "\n";
    }
  }
  std::cerr << "----- (files kept in " << dir_ << ")\n";
}

::testing::AssertionResult same_pixels(const std::filesystem::path& a,
                                       const std::filesystem::path& b) {
  const RgbImage x = read_image(a), y = read_image(b);
  if (x.width != y.width || x.height != y.height) {
    return ::testing::AssertionFailure() << a << " is " << x.width << "x" << x.height << ", " << b
                                         << " is " << y.width << "x" << y.height;
  }
  for (size_t i = 0; i < x.rgb.size(); ++i) {
    if (std::memcmp(&x.rgb[i], &y.rgb[i], sizeof(float)) != 0) {
      const size_t pixel = i / 3;
      return ::testing::AssertionFailure()
             << a << " and " << b << " differ at pixel (" << pixel % size_t(x.width) << ", "
             << pixel / size_t(x.width) << ") channel " << i % 3 << ": " << x.rgb[i] << " vs "
             << y.rgb[i];
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace tessera::e2e
