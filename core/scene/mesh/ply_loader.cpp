#include "scene/mesh/ply_loader.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "scene/mesh/mesh_limits.h"
#include "scene/mesh/ply_attributes.h"
#include "scene/mesh/ply_header.h"
#include "scene/mesh/ply_value_reader.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Names of a vertex's texture coordinates, in the order Mitsuba 3 looks for them; stored as
/// they are (Mitsuba flips no PLY uv).
constexpr std::array<std::array<const char*, 2>, 3> kUvNames = {
    {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}}};

/// For each vertex property: where its value goes (0..2 position, 3..5 normal, 6..7 uv) or -1.
std::vector<int> vertex_slots(const PlyElement& vertex, bool read_normals,
                              const std::string& name) {
  std::vector<int> slots(vertex.properties.size(), -1);
  static const std::array<const char*, 6> kNames = {"x", "y", "z", "nx", "ny", "nz"};
  std::array<int, 6> found;
  for (int k = 0; k < 6; ++k) {
    found[k] = vertex.find(kNames[k]);
    if (found[k] >= 0 && vertex.properties[found[k]].is_list) {
      throw SceneError(name + ": vertex property " + kNames[k] + " must not be a list");
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (found[k] < 0) throw SceneError(name + ": element vertex has no property " + kNames[k]);
    slots[found[k]] = k;
  }
  bool normals = read_normals && found[3] >= 0 && found[4] >= 0 && found[5] >= 0;
  for (int k = 3; k < 6 && normals; ++k) slots[found[k]] = k;
  for (const auto& [u_name, v_name] : kUvNames) {
    int u = vertex.find(u_name);
    int v = vertex.find(v_name);
    if (u < 0 || v < 0) continue;
    if (vertex.properties[u].is_list || vertex.properties[v].is_list) {
      throw SceneError(name + ": vertex properties " + u_name + " and " + v_name +
                       " must not be lists");
    }
    slots[u] = 6;
    slots[v] = 7;
    break;
  }
  return slots;
}

/// The index of the face's vertex index list.
int face_index_list(const PlyElement& face, const std::string& name) {
  int list = face.find("vertex_indices");
  if (list < 0) list = face.find("vertex_index");
  if (list < 0 || !face.properties[list].is_list) {
    throw SceneError(name + ": element face has no list property vertex_indices");
  }
  if (!ply_type_is_integer(face.properties[list].type)) {
    throw SceneError(name + ": face vertex indices must be integers");
  }
  return list;
}

void skip_property(PlyValueReader& in, const PlyProperty& property) {
  if (!property.is_list) return in.skip(property.type);
  int64_t count = in.integer(property.count_type);
  if (count < 0) in.fail("negative list length");
  for (int64_t k = 0; k < count; ++k) in.skip(property.type);
}

/// The vertex attributes: every property but geometry (Mitsuba reserves x, y, z, nx, ny, nz, u,
/// v, and the uv pair it reads under another name).
PlyAttributeLayout vertex_attributes(const PlyElement& vertex, const std::vector<int>& slots) {
  std::vector<bool> reserved(vertex.properties.size());
  for (size_t i = 0; i < reserved.size(); ++i) {
    const std::string& n = vertex.properties[i].name;
    reserved[i] = slots[i] >= 0 || n == "x" || n == "y" || n == "z" || n == "nx" || n == "ny" ||
                  n == "nz" || n == "u" || n == "v";
  }
  return ply_attribute_layout(vertex, "vertex_", reserved);
}

/// Stores property `i`'s value `value` in its attribute, if it has one.
void store_attribute(const PlyAttributeLayout& layout, size_t i, double value, PlyType type,
                     std::vector<float>& row) {
  const PlyAttributeLayout::Slot slot = layout.slots[i];
  if (slot.attribute < 0) return;
  size_t offset = 0;
  for (int a = 0; a < slot.attribute; ++a) offset += size_t(layout.attributes[a].channels);
  row[offset + size_t(slot.channel)] = ply_attribute_value(value, type);
}

/// Appends one row of attribute values (all attributes side by side) `times` times.
void append_rows(const std::vector<float>& row, size_t times,
                 std::vector<MeshAttribute>& attributes) {
  size_t offset = 0;
  for (MeshAttribute& a : attributes) {
    for (size_t t = 0; t < times; ++t) {
      a.values.insert(a.values.end(), row.begin() + offset, row.begin() + offset + a.channels);
    }
    offset += size_t(a.channels);
  }
}

size_t row_width(const PlyAttributeLayout& layout) {
  size_t width = 0;
  for (const MeshAttribute& a : layout.attributes) width += size_t(a.channels);
  return width;
}

void read_vertices(PlyValueReader& in, const PlyElement& vertex, const std::vector<int>& slots,
                   TriangleMesh& mesh) {
  PlyAttributeLayout layout = vertex_attributes(vertex, slots);
  std::vector<float> attribute_row(row_width(layout));
  for (MeshAttribute& a : layout.attributes) a.values.reserve(vertex.count * a.channels);
  bool normals = std::count(slots.begin(), slots.end(), 3) == 1;
  bool uvs = std::count(slots.begin(), slots.end(), 6) == 1;
  mesh.positions.reserve(vertex.count);
  if (normals) mesh.normals.reserve(vertex.count);
  if (uvs) mesh.uvs.reserve(vertex.count);
  for (uint64_t row = 0; row < vertex.count; ++row) {
    in.locate(vertex.name, row);
    std::array<double, 8> v{};
    for (size_t i = 0; i < slots.size(); ++i) {
      if (layout.slots[i].attribute >= 0) {
        double value = in.number(vertex.properties[i].type);
        if (!std::isfinite(value)) in.fail("attribute value is not a finite number");
        store_attribute(layout, i, value, vertex.properties[i].type, attribute_row);
      } else if (slots[i] < 0) {
        skip_property(in, vertex.properties[i]);
      } else {
        v[slots[i]] = in.number(vertex.properties[i].type);
      }
    }
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      in.fail("vertex coordinate is not a finite number");
    }
    mesh.positions.emplace_back(v[0], v[1], v[2]);
    if (normals) mesh.normals.emplace_back(v[3], v[4], v[5]);
    if (uvs) {
      if (!std::isfinite(v[6]) || !std::isfinite(v[7])) {
        in.fail("texture coordinate is not a finite number");
      }
      mesh.uvs.emplace_back(v[6], v[7]);
    }
    append_rows(attribute_row, 1, layout.attributes);
  }
  for (MeshAttribute& a : layout.attributes) mesh.attributes.push_back(std::move(a));
}

/// Appends the fan (0, k, k+1) of `polygon`; counts polygons with fewer than 3 vertices.
/// Returns how many triangles it added.
size_t add_polygon(const std::vector<uint32_t>& polygon, PlyValueReader& in, PlyMesh& out) {
  if (polygon.size() < 3) {
    ++out.dropped_faces;
    return 0;
  }
  if (out.mesh.indices.size() + polygon.size() - 2 > kMaxMeshElements) {
    in.fail("more than " + std::to_string(kMaxMeshElements) + " triangles");
  }
  for (size_t k = 1; k + 1 < polygon.size(); ++k) {
    out.mesh.indices.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
  }
  return polygon.size() - 2;
}

void read_faces(PlyValueReader& in, const PlyElement& face, int list, uint64_t vertex_count,
                PlyMesh& out) {
  out.mesh.indices.reserve(face.count);
  // Face attributes: every scalar property (the index list is a list). A polygon's row is
  // given to each triangle of its fan.
  PlyAttributeLayout layout = ply_attribute_layout(face, "face_", {});
  std::vector<float> values(row_width(layout));
  std::vector<uint32_t> polygon;
  size_t triangles = 0;
  for (uint64_t row = 0; row < face.count; ++row) {
    in.locate(face.name, row);
    for (size_t i = 0; i < face.properties.size(); ++i) {
      const PlyProperty& property = face.properties[i];
      if (layout.slots[i].attribute >= 0) {
        double value = in.number(property.type);
        if (!std::isfinite(value)) in.fail("attribute value is not a finite number");
        store_attribute(layout, i, value, property.type, values);
        continue;
      }
      if (static_cast<int>(i) != list) {
        skip_property(in, property);
        continue;
      }
      int64_t count = in.integer(property.count_type);
      if (count < 0) in.fail("negative vertex count");
      polygon.clear();
      for (int64_t k = 0; k < count; ++k) {
        int64_t index = in.integer(property.type);
        if (index < 0 || static_cast<uint64_t>(index) >= vertex_count) {
          in.fail("vertex index " + std::to_string(index) + " out of range (" +
                  std::to_string(vertex_count) + " vertices)");
        }
        polygon.push_back(static_cast<uint32_t>(index));
      }
      triangles = add_polygon(polygon, in, out);
    }
    append_rows(values, triangles, layout.attributes);
  }
  for (MeshAttribute& a : layout.attributes) out.mesh.attributes.push_back(std::move(a));
}

/// Skips an element we do not use; binary rows without lists are skipped in one step.
void skip_element(PlyValueReader& in, const PlyElement& element, PlyFormat format) {
  bool fixed = std::none_of(element.properties.begin(), element.properties.end(),
                            [](const PlyProperty& p) { return p.is_list; });
  if (fixed && format != PlyFormat::ascii) {
    in.locate(element.name, 0);
    return in.skip_rows(element.count, element.min_row_size(format));
  }
  for (uint64_t row = 0; row < element.count; ++row) {
    in.locate(element.name, row);
    for (const PlyProperty& property : element.properties) skip_property(in, property);
  }
}

void check_limits(const PlyElement& vertex, const PlyElement& face, const std::string& name) {
  if (vertex.count > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(vertex.count) + " vertices (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
  if (face.count > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(face.count) + " faces (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
}

}  // namespace

PlyMesh load_ply(std::string_view bytes, const std::string& name, bool read_normals) {
  PlyHeader header = parse_ply_header(bytes, name);
  const PlyElement* vertex = header.find("vertex");
  const PlyElement* face = header.find("face");
  if (!vertex) throw SceneError(name + ": no vertex element");
  if (!face) throw SceneError(name + ": no face element (only triangle meshes are supported)");
  check_limits(*vertex, *face, name);
  std::vector<int> slots = vertex_slots(*vertex, read_normals, name);
  int list = face_index_list(*face, name);

  size_t first_line = 1 + std::count(bytes.begin(), bytes.begin() + header.data_offset, '\n');
  PlyValueReader in(bytes.substr(header.data_offset), header.format, name, first_line);
  PlyMesh out;
  for (const PlyElement& element : header.elements) {
    if (&element == vertex) {
      read_vertices(in, element, slots, out.mesh);
    } else if (&element == face) {
      read_faces(in, element, list, vertex->count, out);
    } else {
      skip_element(in, element, header.format);
    }
  }
  if (!normals_usable(out.mesh)) out.mesh.normals.clear();
  return out;
}

}  // namespace tessera
