// Stopping a render in the middle of a pixel's samples. A work unit may hold billions of samples
// of one pixel, all in one task: cancelling the TBB group between tasks cannot stop it. The
// renderer's sample loops poll a RenderCancellation instead, every kPollSamples samples per
// thread, and give up with RenderCancelled; nothing of a cancelled render is returned.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>

namespace tessera {

/// Thrown by Renderer::render when its RenderCancellation was cancelled: the partial sums are
/// dropped with the render's stack, so a cancelled unit can never be uploaded or merged.
class RenderCancelled : public std::runtime_error {
 public:
  RenderCancelled() : std::runtime_error("render cancelled") {}
};

/// A cancel flag shared by the thread that decides (a lease watchdog, a signal thread) and the
/// render threads that poll it. cancel() may be called from any thread, any number of times;
/// once cancelled it stays cancelled.
///
/// Cost: the render threads read the flag with a relaxed atomic load once every kPollSamples
/// samples (a counter they keep anyway tells them when), nothing per sample. After cancel(),
/// each render thread traces at most kPollSamples more samples (the scalar order), or one more
/// group of at most kPollSamples paths (the wavefront order), before render() throws.
class RenderCancellation {
 public:
  /// Samples a render thread traces between two polls: a power of two, so the test of the
  /// thread's sample counter is a mask.
  static constexpr uint64_t kPollSamples = uint64_t(1) << 10;
  /// What a render thread may trace after cancel() at most, the promise of docs/renderer.md
  /// ("Cancellation"); kPollSamples is well inside it.
  static constexpr uint64_t kMaxSamplesAfterCancel = uint64_t(1) << 16;
  static_assert(kPollSamples <= kMaxSamplesAfterCancel);

  RenderCancellation() = default;
  RenderCancellation(const RenderCancellation&) = delete;
  RenderCancellation& operator=(const RenderCancellation&) = delete;

  void cancel() noexcept { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const noexcept { return cancelled_.load(std::memory_order_relaxed); }

  /// Called by a render thread with the samples it traced since its last poll (at most about
  /// kPollSamples); true: stop. Runs the poll hook first, when one is set.
  bool poll(uint64_t samples) const {
    if (poll_hook_) poll_hook_(samples);
    return cancelled();
  }

  /// For tests, and for a local time budget (worker/local_render.cpp): `hook(samples)` runs at
  /// every poll, on the polling render thread (concurrently from several threads), before the
  /// flag is read; it may call cancel(). Set it before the render starts.
  void set_poll_hook(std::function<void(uint64_t samples)> hook) { poll_hook_ = std::move(hook); }

 private:
  std::atomic<bool> cancelled_{false};
  std::function<void(uint64_t)> poll_hook_;
};

}  // namespace tessera
