// The farm's store and its lease book, kept in step: one SQLite connection behind one lock, the
// tables' components that act on it (job store, worker registry, lease table), and the lease
// book that answers leases and heartbeats from memory without that lock. Every part of the
// coordinator reads and writes the store through a FarmStore::Lock, which first writes the
// leases the book granted since the last one (flush_leases): whatever the holder reads or
// changes in the store sees every lease answered before it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "clock.h"
#include "job_store.h"
#include "lease_book.h"
#include "lease_table.h"
#include "priority_mutex.h"
#include "spot_checks.h"
#include "store/sqlite.h"
#include "worker_registry.h"

namespace tessera::server {

class FarmStore {
 public:
  /// Opens (creating) the database and applies migrations, then loads each unfinished job into
  /// the lease book as stored. Workers are learnt at registration or at their first call after
  /// a start: start-up reads no worker row. Throws StoreCorrupt for a database damaged where
  /// start-up reads it (the header, the schema), SqliteError for other store errors.
  FarmStore(const std::string& db_path, const Clock& clock, int64_t lease_ms,
            const WorkerHealthPolicy& health);

  /// Whether the last server left the store without a clean shutdown (a crash, a kill), so that
  /// the whole file should be checked; false for a store this start created.
  bool needs_check() const { return needs_check_; }

  /// The store's lock, with the lease book's journal written to the store first.
  class Lock {
   public:
    explicit Lock(FarmStore& store) : lock_(store.mu_) { store.flush_leases(); }

   private:
    std::lock_guard<PriorityMutex> lock_;
  };

  /// The store's lock for a read: the journal is written first when the store can write, and
  /// when it cannot (a full disk: SqliteError) the read goes on without the leases granted since
  /// (they stay in the journal for the next writer), so that reads keep working while writes
  /// fail (docs/reliability.md, "A full disk").
  class ReadLock {
   public:
    explicit ReadLock(FarmStore& store) : lock_(store.mu_) {
      try {
        store.flush_leases();
      } catch (const SqliteError&) {
        // Written by the next Lock or read once the store can write again.
      }
    }

   private:
    std::lock_guard<PriorityMutex> lock_;
  };

  /// Writes the leases the book granted since the last call (and the workers' last calls) in
  /// one transaction; a lease the store refuses is void. Requires the lock. On a store error the
  /// journal is kept for the next call and the error is thrown.
  void flush_leases();
  /// The book's copy of the job, read again from the store (rare events: release, expiry,
  /// submit, resume). Requires the lock and the journal written.
  void reload_job(int64_t job_id);
  /// Records a call of the worker in its last_seen, at most once per touch_interval_ms().
  /// Requires the lock. False when the worker is unknown.
  bool touch_worker(int64_t worker_id, int64_t now_unix_ms);

  /// The lock itself: upload groups take it Deferring (server/priority_mutex.h), and call
  /// flush_leases() themselves.
  PriorityMutex& mutex() { return mu_; }
  // The components below require the lock; book() and checks() do not (each has its own mutex,
  // taken inside the store's lock, never the other way round; checks() before book()).
  Database& db() { return db_; }
  JobStore& jobs() { return jobs_; }
  WorkerRegistry& workers() { return workers_; }
  LeaseTable& leases() { return leases_; }
  LeaseBook& book() { return book_; }
  /// Spot checks and quarantines (server/spot_checks.h): like book(), its own mutex.
  SpotChecks& checks() { return checks_; }
  int64_t lease_ms() const { return leases_.lease_ms(); }
  const Clock& clock() const { return clock_; }

 private:
  /// last_seen's granularity: an eighth of a lease, at most a second (a worker is online for
  /// three lease periods after its last call).
  int64_t touch_interval_ms() const { return std::min<int64_t>(1000, leases_.lease_ms() / 8); }

  const Clock& clock_;
  /// Guards db_ and every component below but book_. A plain caller waits for at most
  /// PriorityMutex::kDeferringTurns group transactions (each group's start and each yield() is
  /// one) beyond the one in progress.
  PriorityMutex mu_;
  Database db_;
  bool needs_check_ = false;
  JobStore jobs_;
  WorkerRegistry workers_;
  LeaseTable leases_;
  LeaseBook book_;
  SpotChecks checks_;
  /// When each worker's last_seen was last written (guarded by mu_): a call within
  /// touch_interval_ms() of it writes nothing (workers are never removed, so the worker exists).
  std::map<int64_t, int64_t> touched_unix_ms_;
  /// Renderer build pins of the jobs leased since the start (flush_leases; a few dozen bytes a
  /// job): a flush reads a job's pin from the store once.
  GrantPins pins_;
};

}  // namespace tessera::server
