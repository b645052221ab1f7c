// A mutex with a lane for short calls that must not queue behind long work (a lease's p99:
// BENCHMARKS.md, "Lease latency and capacity"). The coordinator guards its store with it: an upload
// group (up to ResultIntake::kResultsPerCommit results in one transaction) takes it `Deferring`,
// and every other call takes it plainly (lock/unlock, so std::lock_guard works); leases and
// heartbeats do not take it at all (server/lease_book.h). A Deferring lock is granted only while no
// Urgent caller waits: an urgent call waits for at most the work in progress, never for the uploads
// queued behind it. Urgent callers cannot starve deferring ones for long: each worker makes one
// call at a time and each urgent call is short.
//
// Plain callers are not starved either (with std::mutex, which is unfair, a GetJob was seen to
// wait more than 10 s behind back-to-back upload groups): while a plain caller waits, at most
// `deferring_turns` deferring grants (a group's transaction each: Deferring's constructor and
// each yield()) follow the last plain grant; the next deferring caller then waits until every
// plain caller waiting has had the mutex. Deferring callers are not starved by plain ones: a
// plain grant resets the count, so one deferring grant follows any plain one.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace tessera::server {

class PriorityMutex {
 public:
  /// At most this many deferring grants in a row while a plain caller waits.
  static constexpr int kDeferringTurns = 1;

  explicit PriorityMutex(int deferring_turns = kDeferringTurns)
      : deferring_turns_(deferring_turns < 1 ? 1 : deferring_turns) {}

  /// A plain caller: counted as waiting until it holds the mutex (see the file comment).
  void lock() {
    plain_waiting_.fetch_add(1);
    mu_.lock();
    plain_waiting_.fetch_sub(1);
    deferring_streak_ = 0;
    acquisitions_.fetch_add(1, std::memory_order_relaxed);
  }
  /// Wakes the deferring lockers that waited for the plain callers.
  void unlock() {
    mu_.unlock();
    turns_.notify_all();
  }

  /// Held for a short call: counted as waiting until it holds the mutex, so that no deferring
  /// lock is granted meanwhile; on release, wakes the deferring lockers waiting for their turn.
  class Urgent {
   public:
    explicit Urgent(PriorityMutex& m) : m_(m) {
      m_.urgent_waiting_.fetch_add(1);
      m_.mu_.lock();
      m_.acquisitions_.fetch_add(1, std::memory_order_relaxed);
      m_.urgent_waiting_.fetch_sub(1);
    }
    ~Urgent() {
      m_.mu_.unlock();
      m_.turns_.notify_all();
    }
    Urgent(const Urgent&) = delete;
    Urgent& operator=(const Urgent&) = delete;

   private:
    PriorityMutex& m_;
  };

  /// Held for long work: granted once no Urgent caller waits (re-checked under the mutex).
  class Deferring {
   public:
    explicit Deferring(PriorityMutex& m) : m_(m), lock_(m.mu_, std::defer_lock) { take(); }
    /// Lets the urgent callers waiting now go first: releases the mutex and takes it again once
    /// none waits (at once when none does). A long holder calls it between steps of its work.
    void yield() {
      lock_.unlock();
      take();
    }
    Deferring(const Deferring&) = delete;
    Deferring& operator=(const Deferring&) = delete;

   private:
    void take() {
      m_.deferring_waiting_.fetch_add(1);
      lock_.lock();
      m_.turns_.wait(lock_, [&] {
        return m_.urgent_waiting_.load() == 0 &&
               (m_.plain_waiting_.load() == 0 || m_.deferring_streak_ < m_.deferring_turns_);
      });
      ++m_.deferring_streak_;
      m_.acquisitions_.fetch_add(1, std::memory_order_relaxed);
      m_.deferring_waiting_.fetch_sub(1);
    }
    PriorityMutex& m_;
    std::unique_lock<std::mutex> lock_;
  };

  /// Urgent callers waiting for the mutex (tests line calls up with these).
  int urgent_waiting() const { return urgent_waiting_.load(); }
  /// Plain callers waiting for the mutex (tests line calls up with these).
  int plain_waiting() const { return plain_waiting_.load(); }
  /// Times the mutex was taken, in any lane (tests count a call's acquisitions).
  uint64_t acquisitions() const { return acquisitions_.load(std::memory_order_relaxed); }
  /// Deferring callers that hold or wait for the mutex and have not been granted it yet.
  int deferring_waiting() const { return deferring_waiting_.load(); }

 private:
  std::mutex mu_;
  std::condition_variable turns_;
  std::atomic<int> urgent_waiting_{0};
  std::atomic<int> deferring_waiting_{0};
  std::atomic<int> plain_waiting_{0};
  const int deferring_turns_;
  int deferring_streak_ = 0;  ///< deferring grants since the last plain one (guarded by mu_)
  std::atomic<uint64_t> acquisitions_{0};
};

}  // namespace tessera::server
