// Bounds on what one mesh may hold, checked before allocating (a scene comes from users).
#pragma once

#include <cstdint>

namespace tessera {

/// The most vertices, and the most triangles, one mesh file may declare or produce.
inline constexpr uint64_t kMaxMeshElements = 100'000'000;

}  // namespace tessera
