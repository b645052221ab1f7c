#include "scene/mitsuba/mitsuba_vertex_normals.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace tessera {
namespace {

/// The angle between unit vectors a and b, accurate also near 0 and pi (Mitsuba's unit_angle).
double unit_angle(const glm::dvec3& a, const glm::dvec3& b) {
  double d = glm::dot(a, b);
  double half_chord = 0.5 * glm::length(b - (d >= 0 ? a : -a));
  double angle = 2.0 * std::asin(std::min(half_chord, 1.0));
  return d >= 0 ? angle : std::numbers::pi - angle;
}

}  // namespace

void compute_mitsuba_vertex_normals(TriangleMesh& mesh) {
  std::vector<glm::dvec3> sums(mesh.positions.size(), glm::dvec3(0));
  for (const glm::u32vec3& t : mesh.indices) {
    const glm::dvec3 v[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    glm::dvec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
    double length_sqr = glm::dot(n, n);
    if (!(length_sqr > 0)) continue;
    n /= std::sqrt(length_sqr);
    for (int j = 0; j < 3; ++j) {
      glm::dvec3 to_next = glm::normalize(v[(j + 1) % 3] - v[j]);
      glm::dvec3 to_prev = glm::normalize(v[(j + 2) % 3] - v[j]);
      sums[t[j]] += n * unit_angle(to_next, to_prev);
    }
  }
  mesh.normals.resize(sums.size());
  for (size_t i = 0; i < sums.size(); ++i) {
    double length = glm::length(sums[i]);
    mesh.normals[i] = length > 0 && std::isfinite(length) ? sums[i] / length : glm::dvec3(1, 0, 0);
  }
}

glm::dvec3 stable_unit_vector(const glm::dvec3& n) {
  if (glm::normalize(n) == n) return n;
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(n[a]) > std::abs(n[axis])) axis = a;
  }
  for (int ulps = 1; ulps <= 64; ++ulps) {
    for (double toward : {2.0, -2.0}) {
      glm::dvec3 w = n;
      for (int k = 0; k < ulps; ++k) w[axis] = std::nextafter(w[axis], toward);
      if (glm::normalize(w) == w) return w;
    }
  }
  return n;
}

}  // namespace tessera
