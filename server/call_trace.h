// Per-call timings of the server, for measuring where a call's time goes (BENCHMARKS.md, "Lease
// latency and capacity"). Off unless the environment variable
// TESSERA_CALL_TRACE names a file when the server starts: then each traced event is kept in
// memory and every one is written there when the server stops, a line each: kind, thread id,
// begin, end, a, b, id. Times are
// CLOCK_MONOTONIC nanoseconds, the clock std::chrono::steady_clock reads, so a client on the
// same machine (tessera-bench-merge --trace) can be joined with them. Off, a trace point costs
// one relaxed atomic load.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>

namespace tessera::server::call_trace {

namespace detail {
extern std::atomic<bool> on;
}

/// True when events are being kept.
inline bool enabled() { return detail::on.load(std::memory_order_relaxed); }
/// CLOCK_MONOTONIC in nanoseconds (0 when tracing is off, so an untraced call reads no clock).
int64_t now_ns();
/// Keeps one event: `kind` names it (a string literal), [begin_ns, end_ns], two numbers and an
/// id whose meaning the kind gives. No-op when off.
void record(const char* kind, int64_t begin_ns, int64_t end_ns, int64_t a = 0, int64_t b = 0,
            std::string_view id = {});
/// Reads TESSERA_CALL_TRACE; tracing is on from here when it names a file.
void start_from_environment();
/// Writes every event kept to the file (when on). Returns false when it could not be written.
bool write();

}  // namespace tessera::server::call_trace
