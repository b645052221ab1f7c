// Channels and per-call settings shared by every gRPC client of the farm (the CLI, the worker,
// the tests), and the server's matching limits.
#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <memory>
#include <string>

#include "wire/transport_security.h"

namespace tessera::wire {

/// Largest message either side accepts, bytes: a scene bundle with big meshes, an EXR image, or
/// the accumulation of a 4096x4096 tile all fit.
inline constexpr int kMaxMessageBytes = 1 << 30;

/// Keepalive ping period and how long to wait for its answer, milliseconds. Both ends use them:
/// a dead peer is noticed within about a minute even on an idle connection.
inline constexpr int kKeepaliveTimeMs = 30'000;
inline constexpr int kKeepaliveTimeoutMs = 10'000;

/// Trailing metadata of JobService's GetJob and ListJobs answers while the server's store is
/// damaged (its background check found damage, so it hands out no more work): the one-line
/// damage report, printable ASCII (proto/tessera/v1/job_service.proto). Absent otherwise.
inline constexpr char kStoreDamageMetadata[] = "tessera-store-damage";

/// gRPC's own reconnect backoff on a channel (gRPC's doc/connection-backoff.md): after a failed
/// connection attempt the next starts `initial_ms` later, each delay 1.6 times the last up to
/// `max_ms`, each drawn within +-20 % (kReconnectJitter). While the server is down a channel
/// tries again at least every max_ms x kReconnectJitter; a call made meanwhile fails at once
/// (UNAVAILABLE) unless it waits for the connection (wait_for_ready).
struct ReconnectBackoff {
  int initial_ms = 100;
  int max_ms = 2000;
  /// Not a backoff despite gRPC's name for it (GRPC_ARG_MIN_RECONNECT_BACKOFF_MS): gRPC core
  /// uses it as the minimum *connect timeout* (subchannel.cc, ParseArgsForBackoffValues). At
  /// 100 ms a TCP + HTTP/2 handshake that takes longer (a loaded machine, a link with 50 ms of
  /// latency, TLS) always failed with "connection attempt timed out before receiving SETTINGS
  /// frame" (seen by tests/faults). gRPC's default, 20 s, is what a connection attempt deserves.
  int min_connect_timeout_ms = 20'000;
};

/// gRPC draws each reconnect delay up to this factor above its step.
inline constexpr double kReconnectJitter = 1.2;

/// The arguments of every channel of make_channel: the message size limits, keepalive, and
/// `reconnect`. Exposed so that tests can read what a channel is made with.
grpc::ChannelArguments channel_arguments(const ReconnectBackoff& reconnect = {});

/// A plain-TCP channel to `address` ("host:port") with channel_arguments(). The bearer token is
/// per call (prepare_context), so the channel itself carries no secret.
std::shared_ptr<grpc::Channel> make_channel(const std::string& address);

/// As above over TLS when `tls.active()` (docs/security.md). Throws std::runtime_error when a
/// certificate, key or CA file cannot be read.
std::shared_ptr<grpc::Channel> make_channel(const std::string& address, const ClientTls& tls);

/// As above with the caller's arguments (a worker's own reconnect backoff).
std::shared_ptr<grpc::Channel> make_channel(const std::string& address, const ClientTls& tls,
                                            const grpc::ChannelArguments& args);

/// Sets the call's deadline (now + timeout) and, when `token` is not empty, the metadata
/// `authorization: Bearer <token>`. Every client call goes through this: no call without a
/// deadline.
void prepare_context(grpc::ClientContext& context, const std::string& token,
                     std::chrono::milliseconds timeout);

/// One line for people: "UNAVAILABLE: failed to connect to all addresses".
std::string status_line(const grpc::Status& status);

/// The name of a status code ("DEADLINE_EXCEEDED").
const char* status_code_name(grpc::StatusCode code);

}  // namespace tessera::wire
