// The worker's channel carries the reconnect caps docs/farm.md promises ("Server restart"): gRPC
// tries the server again at least every 1.2 s, inside the worker's 2 s (backoff.h, whose
// sequence backoff_test.cpp checks); and the worker's pause between two tries ends
// when a server answers on the channel, not at the end of its backoff.
#include "worker_client.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <optional>

#include "backoff.h"
#include "wire/rpc_channel.h"

namespace tessera::farm {
namespace {

std::optional<int> worker_channel_int(const grpc::ChannelArguments& args, const char* key) {
  const grpc_channel_args c = args.c_channel_args();
  for (size_t i = 0; i < c.num_args; ++i) {
    if (std::strcmp(c.args[i].key, key) == 0 && c.args[i].type == GRPC_ARG_INTEGER) {
      return c.args[i].value.integer;
    }
  }
  return std::nullopt;
}

TEST(WorkerChannel, ReconnectBackoffIsCappedWithinTheWorkersPromise) {
  const grpc::ChannelArguments args = worker_channel_arguments();
  const std::optional<int> initial =
      worker_channel_int(args, GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS);
  const std::optional<int> max = worker_channel_int(args, GRPC_ARG_MAX_RECONNECT_BACKOFF_MS);
  const std::optional<int> connect_timeout =
      worker_channel_int(args, GRPC_ARG_MIN_RECONNECT_BACKOFF_MS);
  ASSERT_TRUE(initial && max && connect_timeout);
  EXPECT_EQ(*initial, kWorkerReconnect.initial_ms);
  EXPECT_EQ(*max, kWorkerReconnect.max_ms);
  EXPECT_LE(*initial, *max);
  // The longest gap between two connection attempts, gRPC's jitter included, stays within the
  // worker's own cap: the 2 s of docs/farm.md.
  EXPECT_LE(double(*max) * wire::kReconnectJitter, double(Backoff::kMax.count()));
  // A connection attempt still gets gRPC's 20 s to complete (rpc_channel.h).
  EXPECT_GE(*connect_timeout, 20'000);
}

TEST(WorkerChannel, KeepsTheSharedMessageLimitsAndKeepalive) {
  const grpc::ChannelArguments args = worker_channel_arguments();
  EXPECT_EQ(worker_channel_int(args, GRPC_ARG_MAX_RECEIVE_MESSAGE_LENGTH), wire::kMaxMessageBytes);
  EXPECT_EQ(worker_channel_int(args, GRPC_ARG_MAX_SEND_MESSAGE_LENGTH), wire::kMaxMessageBytes);
  EXPECT_EQ(worker_channel_int(args, GRPC_ARG_KEEPALIVE_TIME_MS), wire::kKeepaliveTimeMs);
}

/// A loopback port nothing listens on (bound once by the kernel's choice, then closed).
int unused_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof addr;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size) != 0) {
    if (fd >= 0) close(fd);
    return 0;
  }
  close(fd);
  return ntohs(addr.sin_port);
}

/// A gRPC server on `port` whose WorkerService implements nothing (every call: UNIMPLEMENTED):
/// enough for a channel to connect. nullptr when the port cannot be had.
struct Listener {
  v1::WorkerService::Service service;
  std::unique_ptr<grpc::Server> server;
  void Shutdown() { server->Shutdown(); }
};
std::unique_ptr<Listener> listen_on(int port) {
  auto listener = std::make_unique<Listener>();
  grpc::ServerBuilder builder;
  int selected = 0;
  builder.AddListeningPort("127.0.0.1:" + std::to_string(port), grpc::InsecureServerCredentials(),
                           &selected);
  builder.RegisterService(&listener->service);
  listener->server = builder.BuildAndStart();
  if (!listener->server || selected != port) return nullptr;
  return listener;
}

// Minutes: far beyond gRPC's reconnect cap, so that only a connection ends the pause early.
constexpr std::chrono::milliseconds kLongPause = std::chrono::minutes(5);

/// A client of `port`, where nothing listens yet, whose first call has failed.
std::unique_ptr<WorkerClient> client_after_a_failed_call(int port) {
  auto client = std::make_unique<WorkerClient>("127.0.0.1:" + std::to_string(port), "");
  v1::HeartbeatResponse response;
  EXPECT_FALSE(client->heartbeat({}, &response, std::chrono::milliseconds(200)).ok());
  return client;
}

TEST(WorkerPause, EndsWhenTheServerAnswersAgain) {
  const int port = unused_port();
  ASSERT_NE(port, 0);
  // Nothing listens: a call fails, and the pause after it runs its course.
  const std::unique_ptr<WorkerClient> client = client_after_a_failed_call(port);
  StopSignal stop;
  EXPECT_FALSE(client->pause_until_reconnected(std::chrono::milliseconds(300), stop));
  const std::unique_ptr<Listener> server = listen_on(port);
  ASSERT_TRUE(server);
  // The server is back: the pause ends because the channel connected, not at its end.
  EXPECT_TRUE(client->pause_until_reconnected(kLongPause, stop));
  server->Shutdown();
}

TEST(WorkerPause, AFailureOverALiveConnectionPausesInFull) {
  const int port = unused_port();
  ASSERT_NE(port, 0);
  const std::unique_ptr<Listener> server = listen_on(port);
  ASSERT_TRUE(server);
  WorkerClient client("127.0.0.1:" + std::to_string(port), "");
  StopSignal stop;
  // The server answers UNIMPLEMENTED (its WorkerService implements nothing) over a live
  // connection: as for a busy store's UNAVAILABLE, the pause is the backoff's in full.
  v1::HeartbeatResponse response;
  EXPECT_EQ(client.heartbeat({}, &response, std::chrono::seconds(20)).error_code(),
            grpc::StatusCode::UNIMPLEMENTED);
  EXPECT_FALSE(client.pause_until_reconnected(std::chrono::milliseconds(300), stop));
  server->Shutdown();
}

TEST(WorkerPause, ASignalEndsItButADeliveryPauseOutlastsTheFirst) {
  const int port = unused_port();
  ASSERT_NE(port, 0);
  const std::unique_ptr<WorkerClient> client = client_after_a_failed_call(port);
  StopSignal stop;
  stop.request();
  // The loop's pause ends at the first signal (the worker is leaving)...
  EXPECT_FALSE(client->pause_until_reconnected(kLongPause, stop));
  // ...a delivery's does not: results in hand are still delivered once the server is back.
  const std::unique_ptr<Listener> server = listen_on(port);
  ASSERT_TRUE(server);
  EXPECT_TRUE(client->pause_until_reconnected(kLongPause, stop, 2));
  stop.request();
  EXPECT_FALSE(client->pause_until_reconnected(kLongPause, stop, 2));
  server->Shutdown();
}

}  // namespace
}  // namespace tessera::farm
