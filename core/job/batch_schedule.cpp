#include "job/batch_schedule.h"

#include <algorithm>
#include <bit>

namespace tessera {

std::string_view to_string(BatchKind kind) {
  return kind == BatchKind::progressive ? "progressive" : "fixed";
}

std::optional<BatchKind> batch_kind_from_string(std::string_view name) {
  if (name == "fixed") return BatchKind::fixed;
  if (name == "progressive") return BatchKind::progressive;
  return std::nullopt;
}

namespace {

/// log2 of the progressive cap: batches 1..L double, batch L ends at the cap.
uint32_t cap_log2(uint32_t cap) { return uint32_t(std::bit_width(std::max<uint32_t>(cap, 1)) - 1); }

/// The unclamped end of batch b.
uint64_t raw_end(const BatchSchedule& s, uint32_t b) {
  const uint64_t size = std::max<uint32_t>(s.batch_spp, 1);
  if (s.kind == BatchKind::fixed) return (uint64_t(b) + 1) * size;
  const uint32_t l = cap_log2(s.batch_spp);
  if (b <= l) return uint64_t(1) << b;
  return (uint64_t(b) - l + 1) * size;
}

}  // namespace

uint32_t BatchSchedule::count() const {
  if (spp == 0) return 0;
  const uint64_t size = std::max<uint32_t>(batch_spp, 1);
  if (kind == BatchKind::fixed) return uint32_t((uint64_t(spp) + size - 1) / size);
  const uint32_t l = cap_log2(batch_spp);
  if (spp <= size) return 1 + uint32_t(std::bit_width(spp - 1));  // 1 + ceil(log2(spp))
  return 1 + l + uint32_t((uint64_t(spp) - size + size - 1) / size);
}

uint32_t BatchSchedule::begin(uint32_t b) const { return b == 0 ? 0 : end(b - 1); }

uint32_t BatchSchedule::end(uint32_t b) const {
  return uint32_t(std::min<uint64_t>(raw_end(*this, b), spp));
}

uint32_t BatchSchedule::spp_after(uint32_t merged) const {
  return merged == 0 ? 0 : end(merged - 1);
}

}  // namespace tessera
