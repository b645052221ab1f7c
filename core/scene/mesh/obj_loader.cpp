#include "scene/mesh/obj_loader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <glm/geometric.hpp>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_map>

#include "scene/message_text.h"
#include "scene/mesh/mesh_limits.h"
#include "scene/mesh/mtl_material.h"
#include "scene/mesh/obj_material_reader.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Faces of one material, as tinyobjloader's corners (not yet triangulated).
struct PendingGroup {
  int material_id = -1;
  std::vector<tinyobj::index_t> corners;
  std::vector<unsigned> face_sizes;
  bool all_normals = true;  ///< every corner has a vn
  bool all_uvs = true;      ///< every corner has a vt
};

/// The lines of an OBJ file, each with its 1-based number and without leading blanks.
template <typename Visit>
void for_each_obj_line(const std::string& bytes, Visit&& visit) {
  size_t pos = 0;
  uint64_t number = 0;
  while (pos < bytes.size()) {
    ++number;
    size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    const size_t start = std::min(bytes.find_first_not_of(" \t", pos), end);
    visit(std::string_view(bytes).substr(start, end - start), number);
    pos = end + 1;
  }
}

/// Whether `line` is a statement `keyword` ("v", "vt", "f", ...) followed by a blank.
bool obj_statement(std::string_view line, std::string_view keyword) {
  return line.size() > keyword.size() && line.substr(0, keyword.size()) == keyword &&
         (line[keyword.size()] == ' ' || line[keyword.size()] == '\t');
}

/// Counts of the OBJ elements faces refer to, in the whole file or up to a line.
struct ObjElementCounts {
  uint64_t positions = 0, uvs = 0, normals = 0;
};

/// Refuses files with too many vertex or face lines before tinyobjloader allocates for them, and
/// faces whose indices point at nothing, naming the line and the index as written: tinyobjloader
/// reads an index into an int (99999999999 wraps) and resolves a negative one before the loader
/// sees it, so its message would name another number.
void check_obj_lines(const std::string& bytes, const std::string& path) {
  ObjElementCounts total;
  uint64_t faces = 0;
  for_each_obj_line(bytes, [&](std::string_view line, uint64_t) {
    total.positions += obj_statement(line, "v");
    total.uvs += obj_statement(line, "vt");
    total.normals += obj_statement(line, "vn");
    faces += obj_statement(line, "f");
  });
  if (total.positions > kMaxMeshElements || faces > kMaxMeshElements) {
    throw SceneError(path + ": more than " + std::to_string(kMaxMeshElements) +
                     " vertices or faces");
  }
  ObjElementCounts so_far;
  for_each_obj_line(bytes, [&](std::string_view line, uint64_t number) {
    so_far.positions += obj_statement(line, "v");
    so_far.uvs += obj_statement(line, "vt");
    so_far.normals += obj_statement(line, "vn");
    if (!obj_statement(line, "f")) return;
    const std::string where = path + ": line " + std::to_string(number) + ": a face refers to ";
    // One index: "7" or "-2" of a corner "7/-2/3"; slot 0 vertex, 1 texture coordinate, 2 normal.
    auto check = [&](std::string_view text, int slot) {
      static constexpr const char* kNames[] = {"vertex", "texture coordinate", "normal"};
      const uint64_t all[] = {total.positions, total.uvs, total.normals};
      const uint64_t before[] = {so_far.positions, so_far.uvs, so_far.normals};
      int64_t index = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
      const std::string named = where + kNames[slot] + " " + printable(text);
      if (ec == std::errc::result_out_of_range) {
        throw SceneError(named + " but the file has " + std::to_string(all[slot]));
      }
      if (ec != std::errc() || end != text.data() + text.size()) return;  // tinyobjloader's to say
      if (index == 0) throw SceneError(named + " (OBJ counts from 1)");
      if (index > 0 && uint64_t(index) > all[slot]) {
        throw SceneError(named + " but the file has " + std::to_string(all[slot]));
      }
      if (index < 0 && uint64_t(-(index + 1)) + 1 > before[slot]) {
        throw SceneError(named + ", " + std::to_string(uint64_t(-(index + 1)) + 1) +
                         " back, but only " + std::to_string(before[slot]) + " come before it");
      }
    };
    size_t pos = 1;
    while (pos < line.size()) {
      const size_t start = line.find_first_not_of(" \t\r", pos);
      if (start == std::string_view::npos) break;
      size_t end = line.find_first_of(" \t\r", start);
      if (end == std::string_view::npos) end = line.size();
      const std::string_view corner = line.substr(start, end - start);
      if (corner.front() == '#') break;
      size_t field_start = 0;
      for (int slot = 0; slot < 3 && field_start <= corner.size(); ++slot) {
        size_t slash = corner.find('/', field_start);
        if (slash == std::string_view::npos) slash = corner.size();
        if (slash > field_start) check(corner.substr(field_start, slash - field_start), slot);
        field_start = slash + 1;
      }
      pos = end;
    }
  });
}

/// Sorts the faces of all of tinyobjloader's shapes into one group per material.
std::vector<PendingGroup> group_faces(const std::vector<tinyobj::shape_t>& shapes, bool by_material,
                                      const std::string& path) {
  std::vector<PendingGroup> groups;
  std::unordered_map<int, size_t> slot_of;
  for (const tinyobj::shape_t& shape : shapes) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      unsigned size = mesh.num_face_vertices[f];
      if (offset + size > mesh.indices.size()) {
        throw SceneError(path + ": a face has more than 255 vertices");
      }
      int id = by_material ? mesh.material_ids[f] : -1;
      auto [it, added] = slot_of.try_emplace(id, groups.size());
      if (added) groups.push_back(PendingGroup{id, {}, {}, true, true});
      PendingGroup& group = groups[it->second];
      for (unsigned k = 0; k < size; ++k) {
        group.corners.push_back(mesh.indices[offset + k]);
        group.all_normals = group.all_normals && mesh.indices[offset + k].normal_index >= 0;
        group.all_uvs = group.all_uvs && mesh.indices[offset + k].texcoord_index >= 0;
      }
      group.face_sizes.push_back(size);
      offset += size;
    }
    if (offset != mesh.indices.size()) {
      throw SceneError(path + ": a face has more than 255 vertices");
    }
  }
  return groups;
}

/// A corner's (position, normal, texture coordinate) indices; -1 for an unused one.
struct CornerKey {
  int position, normal, uv;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  size_t operator()(const CornerKey& k) const {
    uint64_t h = (uint64_t(uint32_t(k.position)) << 32) ^ uint32_t(k.normal + 1);
    return std::hash<uint64_t>()(h * 0x9E3779B97F4A7C15ull ^ uint32_t(k.uv + 1));
  }
};

/// Builds one group's mesh: vertices are the distinct (position, normal, uv) triples it uses.
/// OBJ's v points up the image; Mitsuba (and Tessera) look textures up with v pointing down, so
/// a vt (u, v) becomes (u, 1 - v), as Mitsuba's OBJ loader does.
class GroupBuilder {
 public:
  GroupBuilder(const tinyobj::attrib_t& attrib, bool use_normals, bool use_uvs,
               const std::string& path)
      : attrib_(attrib), use_normals_(use_normals), use_uvs_(use_uvs), path_(path) {}

  TriangleMesh build(const PendingGroup& group) {
    size_t offset = 0;
    std::vector<uint32_t> face;
    for (unsigned size : group.face_sizes) {
      face.clear();
      for (unsigned k = 0; k < size; ++k) face.push_back(vertex(group.corners[offset + k]));
      offset += size;
      add_face(face);
    }
    return std::move(mesh_);
  }

 private:
  uint32_t vertex(const tinyobj::index_t& corner) {
    size_t position_count = attrib_.vertices.size() / 3;
    size_t normal_count = attrib_.normals.size() / 3;
    if (corner.vertex_index < 0 || size_t(corner.vertex_index) >= position_count) {
      throw SceneError(path_ + ": a face refers to vertex " +
                       std::to_string(corner.vertex_index + 1) + " but the file has " +
                       std::to_string(position_count));
    }
    int normal = use_normals_ ? corner.normal_index : -1;
    if (use_normals_ && size_t(normal) >= normal_count) {
      throw SceneError(path_ + ": a face refers to normal " + std::to_string(normal + 1) +
                       " but the file has " + std::to_string(normal_count));
    }
    int uv = use_uvs_ ? corner.texcoord_index : -1;
    size_t uv_count = attrib_.texcoords.size() / 2;
    if (use_uvs_ && size_t(uv) >= uv_count) {
      throw SceneError(path_ + ": a face refers to texture coordinate " + std::to_string(uv + 1) +
                       " but the file has " + std::to_string(uv_count));
    }
    CornerKey key{corner.vertex_index, normal, uv};
    auto [it, added] = index_of_.try_emplace(key, uint32_t(mesh_.positions.size()));
    if (added) {
      const double* p = &attrib_.vertices[3 * size_t(corner.vertex_index)];
      mesh_.positions.emplace_back(p[0], p[1], p[2]);
      if (use_normals_) {
        const double* n = &attrib_.normals[3 * size_t(normal)];
        mesh_.normals.emplace_back(n[0], n[1], n[2]);
      }
      if (use_uvs_) {
        const double* t = &attrib_.texcoords[2 * size_t(uv)];
        if (!std::isfinite(t[0]) || !std::isfinite(t[1])) {
          throw SceneError(path_ + ": texture coordinate " + std::to_string(uv + 1) +
                           " is not a finite number");
        }
        mesh_.uvs.emplace_back(t[0], 1 - t[1]);
      }
    }
    return it->second;
  }

  /// Quads split along the shorter diagonal (as tinyobjloader does), larger polygons as a fan.
  void add_face(const std::vector<uint32_t>& f) {
    if (f.size() < 3) return;
    if (mesh_.indices.size() + f.size() - 2 > kMaxMeshElements) {
      throw SceneError(path_ + ": more than " + std::to_string(kMaxMeshElements) + " triangles");
    }
    if (f.size() == 4) {
      const std::vector<glm::dvec3>& p = mesh_.positions;
      double d02 = glm::length(p[f[2]] - p[f[0]]);
      double d13 = glm::length(p[f[3]] - p[f[1]]);
      if (d02 <= d13) {
        mesh_.indices.emplace_back(f[0], f[1], f[2]);
        mesh_.indices.emplace_back(f[0], f[2], f[3]);
      } else {
        mesh_.indices.emplace_back(f[0], f[1], f[3]);
        mesh_.indices.emplace_back(f[1], f[2], f[3]);
      }
      return;
    }
    for (size_t k = 1; k + 1 < f.size(); ++k) mesh_.indices.emplace_back(f[0], f[k], f[k + 1]);
  }

  const tinyobj::attrib_t& attrib_;
  bool use_normals_;
  bool use_uvs_;
  const std::string& path_;
  TriangleMesh mesh_;
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> index_of_;
};

/// The first line of tinyobjloader's error text.
std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  return line.empty() ? "cannot be parsed as OBJ" : printable(line);
}

ObjGroup make_group(const PendingGroup& pending, const tinyobj::attrib_t& attrib,
                    const std::vector<tinyobj::material_t>& materials, const ObjOptions& options,
                    const std::string& path) {
  bool use_normals = !options.face_normals && pending.all_normals && !attrib.normals.empty();
  ObjGroup group;
  bool use_uvs = pending.all_uvs && !attrib.texcoords.empty();
  group.mesh = GroupBuilder(attrib, use_normals, use_uvs, path).build(pending);
  if (!positions_finite(group.mesh)) {
    throw SceneError(path + ": a vertex coordinate is not a finite number");
  }
  if (!normals_usable(group.mesh)) group.mesh.normals.clear();
  if (pending.material_id >= 0 && size_t(pending.material_id) < materials.size()) {
    MtlMaterial mtl = convert_mtl_material(materials[pending.material_id], path);
    group.label = materials[pending.material_id].name;
    group.material = mtl.material;
    group.emission = mtl.emission;
  }
  return group;
}

}  // namespace

ObjMesh load_obj(const std::string& path, const std::string& bytes, const FileReader& reader,
                 const ObjOptions& options) {
  check_obj_lines(bytes, path);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning;
  std::string error;
  std::istringstream stream(bytes);
  ObjMaterialReader material_reader(path, reader);
  bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &stream,
                             options.read_materials ? &material_reader : nullptr,
                             /*triangulate=*/false, /*default_vcols_fallback=*/false);
  if (material_reader.error()) throw SceneError(*material_reader.error());
  if (!ok) throw SceneError(path + ": " + first_line(error));

  ObjMesh result;
  result.mtl_files = material_reader.files();
  for (const PendingGroup& pending : group_faces(shapes, options.read_materials, path)) {
    result.groups.push_back(make_group(pending, attrib, materials, options, path));
  }
  return result;
}

}  // namespace tessera
