#include "scene/native/shape_builders.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>

#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Reads "vertices" as exactly `count` points.
std::vector<glm::dvec3> read_points(const JsonValue& vertices, size_t count) {
  std::vector<glm::dvec3> points;
  for (const JsonValue& v : vertices.elements(count)) points.push_back(v.vec3());
  return points;
}

/// Adds triangle (i, j, k), wound so that its front faces along `outward`.
void add_facing(TriangleMesh& mesh, uint32_t i, uint32_t j, uint32_t k, const glm::dvec3& outward) {
  const std::vector<glm::dvec3>& p = mesh.positions;
  glm::dvec3 n = glm::cross(p[j] - p[i], p[k] - p[i]);
  if (glm::dot(n, outward) < 0) std::swap(j, k);
  mesh.indices.emplace_back(i, j, k);
}

/// Planar within 1e-5 of the quad's size, convex, and split into two proper triangles.
void check_quad(const std::vector<glm::dvec3>& p, const JsonValue& vertices) {
  if (is_degenerate_triangle(p[0], p[1], p[2]) || is_degenerate_triangle(p[0], p[2], p[3])) {
    vertices.fail("quad is degenerate (zero area, or three of its vertices on one line)");
  }
  glm::dvec3 n012 = glm::cross(p[1] - p[0], p[2] - p[0]);
  glm::dvec3 n023 = glm::cross(p[2] - p[0], p[3] - p[0]);
  if (glm::dot(n012, n023) <= 0) {
    vertices.fail("quad is not convex, or its vertices are not in order around it");
  }
  // The plane through the centre, normal to both diagonals.
  glm::dvec3 d02 = p[2] - p[0];
  glm::dvec3 d13 = p[3] - p[1];
  double size = std::max(glm::length(d02), glm::length(d13));
  glm::dvec3 n = glm::normalize(glm::cross(d02, d13));
  glm::dvec3 center = (p[0] + p[1] + p[2] + p[3]) / 4.0;
  double off_plane = 0;
  for (const glm::dvec3& q : p) off_plane = std::max(off_plane, std::abs(glm::dot(q - center, n)));
  if (!(off_plane <= 1e-5 * size)) {
    vertices.fail("quad is not planar (a vertex is " + format_number(off_plane, 3) +
                  " off its plane; the tolerance is 1e-5 of its size)");
  }
}

std::vector<glm::u32vec3> read_indices(const JsonValue& indices, size_t vertex_count) {
  std::vector<glm::u32vec3> result;
  std::vector<JsonValue> triangles = indices.elements();
  if (triangles.empty()) indices.fail("must not be empty");
  for (const JsonValue& triangle : triangles) {
    glm::u32vec3 t;
    std::vector<JsonValue> corners = triangle.elements(3);
    for (int k = 0; k < 3; ++k) {
      int64_t i = corners[k].integer(INT64_MIN, INT64_MAX);
      if (i < 0 || uint64_t(i) >= vertex_count) {
        corners[k].fail("index " + std::to_string(i) + " out of range (" +
                        std::to_string(vertex_count) + " vertices)");
      }
      t[k] = uint32_t(i);
    }
    result.push_back(t);
  }
  return result;
}

}  // namespace

TriangleMesh build_quad(const JsonValue& shape) {
  JsonValue vertices = shape.at("vertices");
  TriangleMesh mesh;
  mesh.positions = read_points(vertices, 4);
  check_quad(mesh.positions, vertices);
  mesh.indices = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh build_triangles(const JsonValue& shape) {
  JsonValue vertices = shape.at("vertices");
  TriangleMesh mesh;
  for (const JsonValue& v : vertices.elements()) mesh.positions.push_back(v.vec3());
  if (mesh.positions.empty()) vertices.fail("must not be empty");
  mesh.indices = read_indices(shape.at("indices"), mesh.positions.size());
  if (std::optional<JsonValue> normals = shape.find("normals")) {
    for (const JsonValue& n : normals->elements(mesh.positions.size())) {
      glm::dvec3 normal = n.vec3();
      if (!(glm::length(normal) > 0) || !std::isfinite(glm::length(normal))) {
        n.fail("must be a non-zero vector");
      }
      mesh.normals.push_back(normal);
    }
  }
  if (std::optional<JsonValue> uvs = shape.find("uvs")) {
    for (const JsonValue& uv : uvs->elements(mesh.positions.size())) {
      std::vector<JsonValue> pair = uv.elements(2);
      mesh.uvs.emplace_back(pair[0].number(), pair[1].number());
    }
  }
  return mesh;
}

TriangleMesh build_box(const JsonValue& shape) {
  glm::dvec3 lo = shape.vec3_or("min", glm::dvec3(-1));
  glm::dvec3 hi = shape.vec3_or("max", glm::dvec3(1));
  for (int a = 0; a < 3; ++a) {
    if (!(lo[a] < hi[a])) {
      throw SceneError(shape.child_path("max") + "[" + std::to_string(a) + "]: must be > min[" +
                       std::to_string(a) + "] (got " + format_number(hi[a]) +
                       " <= " + format_number(lo[a]) + ")");
    }
  }
  TriangleMesh mesh;
  for (uint32_t c = 0; c < 8; ++c) {
    mesh.positions.emplace_back(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
  }
  // Face of axis a at side s: the corners whose bit a is s, in cyclic order around the face.
  for (uint32_t a = 0; a < 3; ++a) {
    uint32_t u = 1u << ((a + 1) % 3), v = 1u << ((a + 2) % 3), bit = 1u << a;
    for (uint32_t s = 0; s < 2; ++s) {
      uint32_t base = s ? bit : 0;
      glm::dvec3 outward(0);
      outward[a] = s ? 1 : -1;
      add_facing(mesh, base, base | u, base | u | v, outward);
      add_facing(mesh, base, base | u | v, base | v, outward);
    }
  }
  return mesh;
}

TriangleMesh build_tetrahedron(const JsonValue& shape) {
  JsonValue vertices = shape.at("vertices");
  TriangleMesh mesh;
  mesh.positions = read_points(vertices, 4);
  const std::vector<glm::dvec3>& p = mesh.positions;
  double longest = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, glm::length(p[j] - p[i]));
  }
  double volume6 = glm::dot(p[1] - p[0], glm::cross(p[2] - p[0], p[3] - p[0]));
  if (!(std::abs(volume6) > 1e-10 * longest * longest * longest)) {
    vertices.fail("tetrahedron is flat (its 4 vertices are in one plane)");
  }
  static const std::array<std::array<uint32_t, 4>, 4> kFaces = {
      {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}}};  // three corners, then the apex
  for (const auto& f : kFaces) add_facing(mesh, f[0], f[1], f[2], p[f[0]] - p[f[3]]);
  return mesh;
}

SphereGeometry build_sphere(const JsonValue& shape) {
  SphereGeometry sphere;
  sphere.center = shape.vec3_or("center", sphere.center);
  if (std::optional<JsonValue> radius = shape.find("radius")) {
    sphere.radius = radius->number();
    if (!(sphere.radius > 0)) {
      radius->fail("must be > 0 (got " + format_number(sphere.radius) + ")");
    }
  }
  if (std::optional<JsonValue> frame = shape.find("frame")) {
    std::vector<JsonValue> rows = frame->elements(3);
    for (int r = 0; r < 3; ++r) {
      glm::dvec3 row = rows[r].vec3();
      for (int c = 0; c < 3; ++c) sphere.frame[c][r] = row[c];
    }
    glm::dmat3 gram = glm::transpose(sphere.frame) * sphere.frame;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        if (std::abs(gram[c][r] - (r == c ? 1.0 : 0.0)) > 1e-6) {
          frame->fail("must be an orthogonal matrix (a rotation, row by row)");
        }
      }
    }
  }
  return sphere;
}

}  // namespace tessera
