#include "lease_reaper.h"

#include <iostream>

namespace tessera::server {

LeaseReaper::LeaseReaper(Coordinator& coordinator, std::chrono::milliseconds period)
    : coordinator_(coordinator), period_(period), thread_([this] { run(); }) {}

LeaseReaper::~LeaseReaper() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void LeaseReaper::run() {
  std::unique_lock lock(mu_);
  while (!cv_.wait_for(lock, period_, [this] { return stop_; })) {
    lock.unlock();
    try {
      const int expired = coordinator_.expire_leases();
      if (expired > 0) std::cerr << "tessera-server: " << expired << " lease(s) expired\n";
      const int deleted = coordinator_.apply_retention();
      if (deleted > 0) {
        std::cerr << "tessera-server: deleted " << deleted
                  << " job(s) past --retention-days\n";
      }
    } catch (const std::exception& e) {
      // A busy or failing store: try again next period.
      std::cerr << "tessera-server: expiring leases: " << e.what() << "\n";
    }
    lock.lock();
  }
}

}  // namespace tessera::server
