// Ctrl-C and SIGTERM for `tessera-worker render`: the render stops within a few thousand
// samples per thread (render/cancellation.h) and the command exits without writing an image,
// instead of leaving the signal's default action to kill it wherever it is. As the farm worker's
// StopSignal (farm/stop_signal.h): no signal handler and no global, the signals are blocked and
// a thread of this object takes them with sigtimedwait.
#pragma once

#include <signal.h>

#include <atomic>
#include <thread>

#include "render/cancellation.h"

namespace tessera {

class SignalCancellation {
 public:
  /// Blocks SIGINT and SIGTERM in the calling thread (threads started later, TBB's included,
  /// inherit the mask: construct it before any render thread exists) and starts the thread
  /// that waits for them. The first signal cancels `cancel`; a second one ends the process at
  /// once with status 128 + the signal's number, for a render stuck where nothing polls (a
  /// BVH build). The destructor stops the thread and restores the mask.
  explicit SignalCancellation(RenderCancellation& cancel);
  ~SignalCancellation();
  SignalCancellation(const SignalCancellation&) = delete;
  SignalCancellation& operator=(const SignalCancellation&) = delete;

  /// The first signal received (SIGINT or SIGTERM), 0 when none.
  int signal_number() const { return signal_.load(); }

 private:
  void run();

  RenderCancellation& cancel_;
  sigset_t signals_{};
  sigset_t previous_mask_{};
  std::atomic<int> signal_{0};
  std::atomic<bool> exit_{false};
  std::thread thread_;
};

}  // namespace tessera
