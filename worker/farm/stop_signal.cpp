#include "stop_signal.h"

namespace tessera::farm {

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
