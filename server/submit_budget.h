// The memory tessera-server may spend checking submitted bundles, all SubmitJob calls together
// (--submit-memory-mb; docs/farm.md, "The server's memory"). Each submit first reserves what its
// check can take, estimated from the bundle's bytes and its files' headers before anything is
// decoded (submit_check_cost); a bundle that needs more than the whole budget is refused, and
// one that needs more than is free waits, first come first served, until the others release
// theirs or its wait ends.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <mutex>
#include <string>

#include "tessera/v1/job.pb.h"

namespace tessera::server {

class SubmitBudget {
 public:
  /// What /metrics shows (tessera_submit_memory_*).
  struct Counters {
    uint64_t capacity_bytes = 0;
    uint64_t reserved_bytes = 0;       ///< reserved now
    uint64_t waiting = 0;              ///< submits waiting for their reservation now
    uint64_t peak_reserved_bytes = 0;  ///< the most reserved at once since start
    uint64_t admitted = 0;             ///< checks that got their reservation
    uint64_t waited = 0;               ///< of those, the ones that had to wait for it
    uint64_t refused_too_large = 0;    ///< needed more than the capacity
    uint64_t refused_busy = 0;         ///< their wait ended first (RESOURCE_EXHAUSTED)
  };

  /// Bytes held for one check until it is destroyed.
  class Reservation {
   public:
    Reservation() = default;
    Reservation(Reservation&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) {
      other.budget_ = nullptr;
    }
    Reservation& operator=(Reservation&&) = delete;
    ~Reservation();
    uint64_t bytes() const { return bytes_; }

   private:
    friend class SubmitBudget;
    Reservation(SubmitBudget* budget, uint64_t bytes) : budget_(budget), bytes_(bytes) {}
    SubmitBudget* budget_ = nullptr;
    uint64_t bytes_ = 0;
  };

  /// `capacity_bytes` > 0.
  explicit SubmitBudget(uint64_t capacity_bytes) : capacity_(capacity_bytes) {}

  /// Reserves `bytes` for checking `what` (a bundle's scene file), waiting at most `max_wait`
  /// behind the reservations held and the submits that asked before. Throws
  /// FarmError(invalid_argument) when `bytes` exceeds the capacity (naming `what`, `detail`, the
  /// size and the flag), FarmError(resource_exhausted) when the wait ends first (naming the flag:
  /// the client may try again).
  Reservation reserve(uint64_t bytes, const std::string& what, const std::string& detail,
                      std::chrono::milliseconds max_wait);

  Counters counters() const;

 private:
  void release(uint64_t bytes);

  const uint64_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable freed_;
  std::list<uint64_t> queue_;  // tickets of the waiting submits, first come first
  uint64_t next_ticket_ = 0;
  Counters counters_;
};

/// What checking a bundle may take (SubmitBudget::reserve).
struct SubmitCost {
  uint64_t bytes = 0;
  std::string largest_file;         ///< the file whose decoding costs the most ("" when none)
  uint64_t largest_file_bytes = 0;  ///< its share of `bytes`
};

/// The memory the submit check of `bundle` may take, from its bytes and its files' headers
/// (nothing is decoded): three copies of the bundle's bytes (the parsed contents, the file
/// reader's and the canonical bundle), plus per file what decoding it takes: a Mitsuba
/// serialized mesh three times its shapes' arrays (serialized_load_bytes: the loaded arrays, the
/// scene's copy, what the parser adds), a PLY or OBJ mesh 8 times its bytes, a volume grid
/// (.vol) its bytes, an image image_check_memory of its header. Files are counted once: a scene
/// that loads one mesh file many times costs more (docs/farm.md). Throws
/// FarmError(invalid_argument) naming the file for an image of more than `max_texture_values`
/// values (--max-texture-values).
SubmitCost submit_check_cost(const v1::SceneBundle& bundle, uint64_t max_texture_values);

}  // namespace tessera::server
