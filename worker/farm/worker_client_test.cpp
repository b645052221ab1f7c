// The worker's channel carries the reconnect caps docs/farm.md promises ("Server restart"): gRPC
// tries the server again at least every 1.2 s, inside the worker's 2 s (backoff.h, whose
// sequence tests/farm/backoff_test.cpp checks).
#include "worker_client.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tessera::farm
