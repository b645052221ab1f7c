#include "scene/mitsuba/mitsuba_shape_geometry.h"

#include <cmath>
#include <numbers>

namespace tessera {

MitsubaBuiltinMesh mitsuba_rectangle() {
  MitsubaBuiltinMesh out;
  out.mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  out.mesh.indices = {{0, 1, 2}, {0, 2, 3}};
  for (const glm::dvec3& p : out.mesh.positions) out.uvs.emplace_back((p.x + 1) / 2, (p.y + 1) / 2);
  return out;
}

MitsubaBuiltinMesh mitsuba_cube() {
  // Mitsuba's cube.cpp: corner c sits at (+-1, +-1, +-1), bit k of c giving the sign of axis k;
  // vertex 4s + k of face s is corner kCorner[4s + k] with uv kUv[k].
  static constexpr uint32_t kCorner[24] = {1, 5, 4, 0, 3, 2, 6, 7, 1, 3, 7, 5,
                                           5, 7, 6, 4, 4, 6, 2, 0, 3, 1, 0, 2};
  static constexpr double kUv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  MitsubaBuiltinMesh out;
  for (uint32_t v = 0; v < 24; ++v) {
    uint32_t c = kCorner[v];
    out.mesh.positions.emplace_back(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
    out.uvs.emplace_back(kUv[v % 4][0], kUv[v % 4][1]);
  }
  for (uint32_t s = 0; s < 6; ++s) {
    uint32_t v = 4 * s;
    out.mesh.indices.emplace_back(v, v + 1, v + 2);
    out.mesh.indices.emplace_back(v + 3, v, v + 2);
  }
  return out;
}

MitsubaBuiltinMesh mitsuba_disk() {
  MitsubaBuiltinMesh out;
  const int n = kMitsubaDiskSegments;
  for (int k = 0; k <= n; ++k) {  // the rim; vertex n closes it at v = 1
    double phi = 2 * std::numbers::pi * (k % n) / n;
    out.mesh.positions.emplace_back(std::cos(phi), std::sin(phi), 0);
    out.uvs.emplace_back(1.0, double(k) / n);
  }
  for (uint32_t k = 0; k < uint32_t(n); ++k) {
    uint32_t centre = uint32_t(out.mesh.positions.size());
    out.mesh.positions.emplace_back(0, 0, 0);
    out.uvs.emplace_back(0.0, (k + 0.5) / n);
    out.mesh.indices.emplace_back(centre, k, k + 1);
  }
  return out;
}

}  // namespace tessera
