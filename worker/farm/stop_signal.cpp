#include "stop_signal.h"

#include <cerrno>
#include <ctime>

namespace tessera::farm {

StopSignal::StopSignal() {
  sigemptyset(&signals_);
  sigaddset(&signals_, SIGTERM);
  sigaddset(&signals_, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals_, &previous_mask_);
  thread_ = std::thread([this] { run(); });
}

StopSignal::~StopSignal() {
  exit_ = true;
  thread_.join();
  pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
}

void StopSignal::run() {
  // sigtimedwait with a short timeout so the destructor can end this thread without a signal.
  const timespec timeout{0, 100'000'000};
  while (!exit_) {
    const int signal_number = sigtimedwait(&signals_, nullptr, &timeout);
    if (signal_number == SIGTERM || signal_number == SIGINT) request();
  }
}

void StopSignal::request() {
  {
    std::lock_guard lock(mu_);
    count_.fetch_add(1);
    if (cancellable_) cancellable_->TryCancel();
  }
  cv_.notify_all();
}

bool StopSignal::wait_for(std::chrono::milliseconds duration) {
  std::unique_lock lock(mu_);
  cv_.wait_for(lock, duration, [this] { return count_.load() > 0; });
  return count_.load() > 0;
}

void StopSignal::set_cancellable(grpc::ClientContext* context) {
  std::lock_guard lock(mu_);
  cancellable_ = context;
  if (cancellable_ && count_.load() > 0) cancellable_->TryCancel();
}

}  // namespace tessera::farm
