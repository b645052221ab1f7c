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

MitsubaBuiltinMesh mitsuba_cylinder() {
  MitsubaBuiltinMesh out;
  const int n = kMitsubaDiskSegments;
  for (int k = 0; k <= n; ++k) {  // column k at phi = 2 pi k / n; column n closes the seam
    double phi = 2 * std::numbers::pi * (k % n) / n;
    glm::dvec3 radial(std::cos(phi), std::sin(phi), 0);
    for (int z = 0; z < 2; ++z) {
      out.mesh.positions.push_back(radial + glm::dvec3(0, 0, z));
      out.mesh.normals.push_back(radial);
      out.uvs.emplace_back(double(k) / n, double(z));
    }
  }
  for (uint32_t k = 0; k < uint32_t(n); ++k) {
    uint32_t a0 = 2 * k, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
    out.mesh.indices.emplace_back(a0, b0, b1);
    out.mesh.indices.emplace_back(a0, b1, a1);
  }
  return out;
}

glm::dmat4 mitsuba_cylinder_placement(const glm::dvec3& p0, const glm::dvec3& p1, double radius) {
  glm::dvec3 d = p1 - p0;
  double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  glm::dvec3 n = d / length;
  // Mitsuba's coordinate_system(n): the frame's s and t.
  double sign = std::copysign(1.0, n.z);
  double a = -1.0 / (sign + n.z);
  double b = n.x * n.y * a;
  glm::dvec3 s(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  glm::dvec3 t(b, sign + n.y * n.y * a, -n.y);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(s * radius, 0);
  m[1] = glm::dvec4(t * radius, 0);
  m[2] = glm::dvec4(n * length, 0);
  m[3] = glm::dvec4(p0, 1);
  return m;
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
