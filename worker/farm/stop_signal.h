// SIGTERM/SIGINT for the worker (taken by a SignalThread, cli/signal_thread.h): recorded here, and
// the call in flight (a long poll) cancelled so the worker reacts at once.
#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "cli/signal_thread.h"

namespace tessera::farm {

class StopSignal {
 public:
  /// Blocks SIGTERM and SIGINT in the calling thread (threads started later inherit the mask)
  /// and starts the thread that waits for them. The destructor stops it and restores the mask.
  StopSignal() = default;
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  /// Signals received so far: 0 run, 1 finish the unit in hand then exit, 2+ abandon it.
  int count() const { return count_.load(); }
  bool requested() const { return count() > 0; }

  /// Sleeps up to `duration`, waking early when a signal arrives. Returns requested().
  bool wait_for(std::chrono::milliseconds duration);

  /// The call to cancel when a signal arrives (nullptr: none). Used around long polls.
  void set_cancellable(grpc::ClientContext* context);

  /// Records a stop as a signal would (for tests and for fatal conditions).
  void request();

 private:
  std::atomic<int> count_{0};
  mutable std::mutex mu_;
  std::condition_variable cv_;
  grpc::ClientContext* cancellable_ = nullptr;  ///< guarded by mu_
  SignalThread signals_{[this](int) { request(); }};  ///< last: it stops first
};

}  // namespace tessera::farm
