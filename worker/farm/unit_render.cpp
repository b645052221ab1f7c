#include "unit_render.h"

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace tessera::farm {

UnitRenderResult render_unit(const Renderer& renderer, tbb::task_arena& arena, const TileRect& tile,
                             uint32_t sample_begin, uint32_t sample_end,
                             const std::function<LeaseCheck()>& heartbeat,
                             std::chrono::milliseconds heartbeat_interval, const StopSignal& stop) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  UnitRenderResult out;
  RenderCancellation cancellation;
  std::atomic<int> cancelled_as{0};  // 0 none, 1 lease lost, 2 abandoned
  std::mutex mu;
  std::condition_variable cv;
  bool done = false;

  std::thread watchdog([&] {
    // Checks for a second signal often (100 ms), heartbeats at the server's interval.
    auto next_heartbeat = clock::now() + heartbeat_interval;
    std::unique_lock lock(mu);
    while (!done) {
      cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return done; });
      if (done) break;
      if (stop.count() >= 2) {
        cancelled_as = 2;
        cancellation.cancel();
        break;
      }
      if (clock::now() < next_heartbeat) continue;
      lock.unlock();
      const LeaseCheck check = heartbeat();
      lock.lock();
      next_heartbeat = clock::now() + heartbeat_interval;
      if (check == LeaseCheck::gone) {
        cancelled_as = 1;
        cancellation.cancel();
        break;
      }
    }
  });

  const auto stop_watchdog = [&] {
    {
      std::lock_guard lock(mu);
      done = true;
    }
    cv.notify_all();
    watchdog.join();
  };
  try {
    arena.execute([&] {
      out.result = renderer.render(tile, sample_begin, sample_end, &out.stats, &cancellation);
    });
  } catch (const RenderCancelled&) {
    // cancelled_as says why; the partial sums went with the renderer's stack.
  } catch (...) {
    stop_watchdog();
    throw;
  }
  stop_watchdog();

  out.elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(clock::now() - start);
  // A unit cancelled after its last poll may have finished: it is dropped all the same.
  if (cancelled_as != 0) out.result = Accumulation();
  if (cancelled_as == 1) out.outcome = UnitOutcome::lease_lost;
  if (cancelled_as == 2) out.outcome = UnitOutcome::abandoned;
  return out;
}

}  // namespace tessera::farm
