// Ctrl-C and SIGTERM for `tessera-worker render`: the render stops within a few thousand
// samples per thread (render/cancellation.h) and the command exits without writing an image,
// instead of leaving the signal's default action to kill it wherever it is. The signals are
// taken by a SignalThread (cli/signal_thread.h), as the farm worker's StopSignal takes them.
#pragma once

#include <atomic>

#include "render/cancellation.h"
#include "cli/signal_thread.h"

namespace tessera {

class SignalCancellation {
 public:
  /// Blocks SIGINT and SIGTERM in the calling thread (threads started later, TBB's included,
  /// inherit the mask: construct it before any render thread exists) and starts the thread
  /// that waits for them. The first signal cancels `cancel`; a second one ends the process at
  /// once with status 128 + the signal's number, for a render stuck where nothing polls (a
  /// BVH build). The destructor stops the thread and restores the mask.
  explicit SignalCancellation(RenderCancellation& cancel) : cancel_(cancel) {}
  SignalCancellation(const SignalCancellation&) = delete;
  SignalCancellation& operator=(const SignalCancellation&) = delete;

  /// The first signal received (SIGINT or SIGTERM), 0 when none.
  int signal_number() const { return signal_.load(); }

 private:
  void on_signal(int number);

  RenderCancellation& cancel_;
  std::atomic<int> signal_{0};
  SignalThread signals_{[this](int number) { on_signal(number); }};  ///< last: it stops first
};

}  // namespace tessera
