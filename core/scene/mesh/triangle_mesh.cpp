#include "scene/mesh/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

namespace tessera {

void transform_mesh(TriangleMesh& mesh, const Transform& transform) {
  for (glm::dvec3& p : mesh.positions) p = transform.point(p);
  for (glm::dvec3& n : mesh.normals) n = transform.normal(n);
  if (transform.flips_orientation()) {
    for (glm::u32vec3& t : mesh.indices) std::swap(t.y, t.z);
  }
}

void flip_mesh(TriangleMesh& mesh) {
  for (glm::u32vec3& t : mesh.indices) std::swap(t.y, t.z);
  for (glm::dvec3& n : mesh.normals) n = -n;
}

double triangle_area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

bool is_degenerate_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 e1 = b - a;
  glm::dvec3 e2 = c - a;
  return glm::length(glm::cross(e1, e2)) <= 1e-12 * glm::length(e1) * glm::length(e2);
}

double mesh_area(const TriangleMesh& mesh) {
  double area = 0;
  for (const glm::u32vec3& t : mesh.indices) {
    area += triangle_area(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]);
  }
  return area;
}

std::optional<size_t> first_degenerate_triangle(const TriangleMesh& mesh) {
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    const glm::u32vec3& t = mesh.indices[i];
    if (is_degenerate_triangle(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z])) {
      return i;
    }
  }
  return std::nullopt;
}

size_t drop_degenerate_triangles(TriangleMesh& mesh) {
  const size_t before = mesh.indices.size();
  size_t kept = 0;
  for (size_t i = 0; i < before; ++i) {
    const glm::u32vec3 t = mesh.indices[i];
    if (is_degenerate_triangle(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z])) {
      continue;
    }
    for (MeshAttribute& a : mesh.attributes) {
      if (a.per_vertex()) continue;
      const size_t c = size_t(a.channels);
      std::copy_n(a.values.begin() + i * c, c, a.values.begin() + kept * c);
    }
    mesh.indices[kept++] = t;
  }
  mesh.indices.resize(kept);
  for (MeshAttribute& a : mesh.attributes) {
    if (!a.per_vertex()) a.values.resize(kept * size_t(a.channels));
  }
  return before - kept;
}

bool positions_finite(const TriangleMesh& mesh) {
  return std::all_of(mesh.positions.begin(), mesh.positions.end(), [](const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  });
}

bool normals_usable(const TriangleMesh& mesh) {
  return std::all_of(mesh.normals.begin(), mesh.normals.end(), [](const glm::dvec3& n) {
    double length = glm::length(n);
    return std::isfinite(length) && length > 0;
  });
}

}  // namespace tessera
