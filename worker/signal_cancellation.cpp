#include "signal_cancellation.h"

#include <cstdlib>
#include <ctime>

namespace tessera {

SignalCancellation::SignalCancellation(RenderCancellation& cancel) : cancel_(cancel) {
  sigemptyset(&signals_);
  sigaddset(&signals_, SIGINT);
  sigaddset(&signals_, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals_, &previous_mask_);
  thread_ = std::thread([this] { run(); });
}

SignalCancellation::~SignalCancellation() {
  exit_ = true;
  thread_.join();
  pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
}

void SignalCancellation::run() {
  // A short timeout, so that the destructor can end this thread without a signal.
  const timespec timeout{0, 100'000'000};
  while (!exit_) {
    const int received = sigtimedwait(&signals_, nullptr, &timeout);
    if (received != SIGINT && received != SIGTERM) continue;
    int none = 0;
    if (!signal_.compare_exchange_strong(none, received)) std::_Exit(128 + received);
    cancel_.cancel();
  }
}

}  // namespace tessera
