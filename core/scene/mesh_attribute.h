// Mitsuba's mesh attributes: values per vertex or per face of a triangle mesh, read from PLY
// files and looked up by the `mesh_attribute` texture (docs/scenes.md, "Mesh attributes").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tessera {

/// One attribute of a triangle mesh. Its name says what it is attached to, as in Mitsuba:
/// "vertex_<name>" has one row per vertex (interpolated over a triangle by barycentrics),
/// "face_<name>" one row per triangle (constant over it). Rows hold `channels` floats (1 or 3),
/// stored as Mitsuba stores them (single precision, linear: integer PLY values are already
/// normalised and sRGB-decoded by the reader).
struct MeshAttribute {
  std::string name;
  int channels = 1;
  std::vector<float> values;  ///< rows * channels, row-major

  bool per_vertex() const { return is_vertex_attribute_name(name); }
  size_t rows() const { return channels > 0 ? values.size() / size_t(channels) : 0; }
  bool operator==(const MeshAttribute&) const = default;

  static bool is_vertex_attribute_name(std::string_view n) { return n.starts_with("vertex_"); }
  static bool is_face_attribute_name(std::string_view n) { return n.starts_with("face_"); }
};

/// The attribute named `name` in `attributes`, or nullptr.
const MeshAttribute* find_mesh_attribute(const std::vector<MeshAttribute>& attributes,
                                         std::string_view name);

/// Checks `attributes` of a mesh with `vertices` vertices and `triangles` triangles: names start
/// with "vertex_" or "face_" and are unique, 1 or 3 channels, one row per vertex or per
/// triangle, finite values. Returns "" when they are fine, else what is wrong (naming the
/// attribute).
std::string mesh_attributes_problem(const std::vector<MeshAttribute>& attributes,
                                    size_t vertices, size_t triangles);

}  // namespace tessera
