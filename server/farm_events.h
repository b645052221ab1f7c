// What the farm's parts tell the waiting calls: `changes` wakes whoever shows the farm (WatchJob
// streams, the dashboard), `work` the workers long-polling LeaseUnit (a subset of changes: only
// when a unit may have become leasable).
#pragma once

#include "change_notifier.h"

namespace tessera::server {

struct FarmEvents {
  ChangeNotifier changes;
  ChangeNotifier work;

  /// Notifies changes, and work too when `frees_work` (the change may let a unit be leased).
  void notify(bool frees_work) {
    changes.notify();
    if (frees_work) work.notify();
  }
  /// No more leases: long polls and watches end, now and later.
  void stop() {
    changes.stop();
    work.stop();
  }
};

}  // namespace tessera::server
