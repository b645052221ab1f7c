#include "deliveries.h"

#include <utility>

namespace tessera::farm {

Deliveries::Deliveries(Deliver deliver)
    : deliver_(std::move(deliver)), thread_([this] { run(); }) {}

Deliveries::~Deliveries() {
  {
    std::lock_guard lock(mu_);
    quit_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void Deliveries::start(std::vector<v1::UploadResultRequest> results) {
  std::unique_lock lock(mu_);
  cv_.wait(lock, [&] { return !busy_; });
  rethrow(lock);
  if (results.empty()) return;
  for (const v1::UploadResultRequest& r : results) in_flight_.push_back(r.lease_id());
  pending_ = std::move(results);
  busy_ = true;
  cv_.notify_all();
}

void Deliveries::wait() {
  std::unique_lock lock(mu_);
  cv_.wait(lock, [&] { return !busy_; });
  rethrow(lock);
}

void Deliveries::rethrow_if_failed() {
  std::unique_lock lock(mu_);
  if (!busy_) rethrow(lock);
}

std::vector<std::string> Deliveries::in_flight() const {
  std::lock_guard lock(mu_);
  return in_flight_;
}

void Deliveries::rethrow(std::unique_lock<std::mutex>&) {
  if (!error_) return;
  std::exception_ptr error = std::exchange(error_, nullptr);
  std::rethrow_exception(error);
}

void Deliveries::run() {
  std::unique_lock lock(mu_);
  for (;;) {
    cv_.wait(lock, [&] { return quit_ || pending_; });
    if (!pending_) return;  // quit, nothing left
    std::vector<v1::UploadResultRequest> results = std::move(*pending_);
    pending_.reset();
    lock.unlock();
    std::exception_ptr error;
    try {
      deliver_(results);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    in_flight_.clear();
    busy_ = false;
    cv_.notify_all();
  }
}

}  // namespace tessera::farm
