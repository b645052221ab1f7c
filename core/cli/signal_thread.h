// SIGINT and SIGTERM without a signal handler or a global, for the farm worker's StopSignal
// (worker/farm/stop_signal.h) and the local render's SignalCancellation
// (worker/signal_cancellation.h): the signals are blocked and a thread of this object takes them
// with sigtimedwait and hands each to a callback, which may do anything a thread may (lock,
// notify, cancel a gRPC call).
#pragma once

#include <signal.h>

#include <atomic>
#include <ctime>
#include <functional>
#include <thread>

namespace tessera {

class SignalThread {
 public:
  /// Blocks SIGINT and SIGTERM in the calling thread (threads started later inherit the mask:
  /// construct it before any worker thread exists) and starts the thread that calls
  /// `on_signal(number)` for each one received. The destructor stops that thread (within
  /// 0.1 s) and restores the mask.
  explicit SignalThread(std::function<void(int)> on_signal) : on_signal_(std::move(on_signal)) {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, &previous_mask_);
    thread_ = std::thread([this] { run(); });
  }
  ~SignalThread() {
    exit_ = true;
    thread_.join();
    pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
  }
  SignalThread(const SignalThread&) = delete;
  SignalThread& operator=(const SignalThread&) = delete;

 private:
  void run() {
    // A short timeout, so that the destructor can end this thread without a signal.
    const timespec timeout{0, 100'000'000};
    while (!exit_) {
      const int received = sigtimedwait(&signals_, nullptr, &timeout);
      if (received == SIGINT || received == SIGTERM) on_signal_(received);
    }
  }

  std::function<void(int)> on_signal_;
  sigset_t signals_{};
  sigset_t previous_mask_{};
  std::atomic<bool> exit_{false};
  std::thread thread_;
};

}  // namespace tessera
