// Group commit: calls that arrive while a commit is in progress are committed together, in one
// commit, by the first of them once that commit ends (leader and followers, no timer). Under load
// many uploads wait on the store's lock at once; committing them in one transaction pays
// BEGIN/COMMIT and the WAL's commit once for all of them (BENCHMARKS.md, "Lease latency and
// capacity"). A call alone is committed at once: nothing ever waits for company.
//
// `commit` receives the calls of one group in arrival order and records each call's answer in
// the call itself (Call holds its input and its outcome). Should it throw, every call of the
// group gets that exception from run().
//
// A group is bounded: it takes waiting calls in arrival order while their weight (`weight`,
// e.g. the results a call carries) stays within `max_weight`, and always at least one call; the
// calls left over wait for the next group. The coordinator's upload groups hold the store's
// lock for the group's transaction but give way to a waiting lease between two calls
// (ResultIntake::commit_uploads).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <utility>
#include <vector>

namespace tessera::server {

template <typename Call>
class GroupCommit {
 public:
  using Commit = std::function<void(const std::vector<Call*>&)>;
  using Weight = std::function<size_t(const Call&)>;

  /// Unbounded groups: every call waiting joins the next.
  explicit GroupCommit(Commit commit) : commit_(std::move(commit)) {}
  /// Groups of at most `max_weight` (each call weighs `weight(call)`; a heavier call goes alone).
  GroupCommit(Commit commit, Weight weight, size_t max_weight)
      : commit_(std::move(commit)), weight_(std::move(weight)), max_weight_(max_weight) {}

  /// Returns once `call` was committed, alone or with the calls waiting beside it.
  void run(Call& call) {
    Waiter me;
    me.call = &call;
    std::unique_lock lock(mu_);
    queue_.push_back(&me);
    for (;;) {
      // Each call sleeps on its own condition: a finished group wakes its calls and the next
      // leader only, not every call waiting (with 256 workers uploading, waking all of them
      // after each bounded group cost more CPU than the group saved).
      me.cv.wait(lock, [&] { return me.done || (!committing_ && queue_.front() == &me); });
      if (me.done) break;
      // No commit in progress and this call is the oldest waiting: it leads the group of the
      // calls waiting now, oldest first (itself among them), up to the weight bound.
      committing_ = true;
      std::vector<Waiter*> group = take_group();
      lock.unlock();
      std::vector<Call*> calls;
      calls.reserve(group.size());
      for (Waiter* w : group) calls.push_back(w->call);
      std::exception_ptr error;
      try {
        commit_(calls);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      for (Waiter* w : group) {
        w->done = true;
        w->error = error;
        if (w != &me) w->cv.notify_one();
      }
      ++groups_;
      calls_ += group.size();
      committing_ = false;
      if (!queue_.empty()) queue_.front()->cv.notify_one();  // the next group's leader
    }
    if (me.error) std::rethrow_exception(me.error);
  }

  /// Calls waiting for a commit (tests use it to line calls up).
  size_t waiting() {
    std::lock_guard lock(mu_);
    return queue_.size();
  }
  /// Groups committed and calls in them since construction.
  std::pair<uint64_t, uint64_t> committed() {
    std::lock_guard lock(mu_);
    return {groups_, calls_};
  }

 private:
  struct Waiter {
    Call* call = nullptr;
    bool done = false;
    std::exception_ptr error;
    std::condition_variable cv;  ///< woken when done, or when it is to lead the next group
  };

  /// The oldest waiting calls within the weight bound (at least one), removed from the queue.
  /// Requires mu_.
  std::vector<Waiter*> take_group() {
    size_t n = queue_.size();
    if (weight_) {
      size_t total = 0;
      for (n = 0; n < queue_.size(); ++n) {
        total += weight_(*queue_[n]->call);
        if (n > 0 && total > max_weight_) break;
      }
    }
    std::vector<Waiter*> group(queue_.begin(), queue_.begin() + std::ptrdiff_t(n));
    queue_.erase(queue_.begin(), queue_.begin() + std::ptrdiff_t(n));
    return group;
  }

  Commit commit_;
  Weight weight_;  ///< empty: groups unbounded
  size_t max_weight_ = 0;
  std::mutex mu_;
  std::vector<Waiter*> queue_;  ///< calls not committed yet, in arrival order
  bool committing_ = false;
  uint64_t groups_ = 0, calls_ = 0;
};

}  // namespace tessera::server
