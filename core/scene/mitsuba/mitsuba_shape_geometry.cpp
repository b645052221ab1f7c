#include "scene/mitsuba/mitsuba_shape_geometry.h"

#include <cmath>
#include <numbers>

namespace tessera {

TriangleMesh mitsuba_rectangle() {
  TriangleMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.indices = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh mitsuba_cube() {
  TriangleMesh mesh;
  for (uint32_t c = 0; c < 8; ++c) {
    mesh.positions.emplace_back(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
  }
  // Face of axis a at side s: its corners are those whose bit a is s. Going around it through
  // the other two axes u, v (in cyclic order after a) is counter-clockwise seen from +a, so the
  // side at -a takes the reverse order.
  for (uint32_t a = 0; a < 3; ++a) {
    uint32_t bit = 1u << a, u = 1u << ((a + 1) % 3), v = 1u << ((a + 2) % 3);
    for (uint32_t s = 0; s < 2; ++s) {
      uint32_t base = s ? bit : 0;
      uint32_t p0 = base, p1 = base | u, p2 = base | u | v, p3 = base | v;
      if (s) {
        mesh.indices.emplace_back(p0, p1, p2);
        mesh.indices.emplace_back(p0, p2, p3);
      } else {
        mesh.indices.emplace_back(p0, p2, p1);
        mesh.indices.emplace_back(p0, p3, p2);
      }
    }
  }
  return mesh;
}

TriangleMesh mitsuba_disk() {
  TriangleMesh mesh;
  mesh.positions.emplace_back(0, 0, 0);
  for (int k = 0; k < kMitsubaDiskSegments; ++k) {
    double phi = 2 * std::numbers::pi * k / kMitsubaDiskSegments;
    mesh.positions.emplace_back(std::cos(phi), std::sin(phi), 0);
  }
  for (uint32_t k = 0; k < uint32_t(kMitsubaDiskSegments); ++k) {
    mesh.indices.emplace_back(0, 1 + k, 1 + (k + 1) % kMitsubaDiskSegments);
  }
  return mesh;
}

}  // namespace tessera
