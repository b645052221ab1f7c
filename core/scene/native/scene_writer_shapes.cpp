#include "scene/native/scene_writer_shapes.h"

#include <glm/gtc/matrix_access.hpp>

#include "scene/native/material_parser.h"
#include "scene/scene_error.h"

namespace tessera::scene_writer {

namespace {

void append_points(std::string& out, const char* key, const std::vector<glm::dvec3>& points,
                   const std::string& what) {
  out += ",\n      \"";
  out += key;
  out += "\": [";
  for (size_t i = 0; i < points.size(); ++i) {
    out += i ? ",\n        " : "\n        ";
    out += vec3(points[i], what);
  }
  out += "\n      ]";
}

/// A curves shape's "control_points" ([x, y, z, radius] each) and "curve_sizes".
void append_curves(std::string& out, const Shape& s, const std::string& what) {
  uint64_t total = 0;
  for (uint32_t n : s.curve_sizes) total += n;
  if (s.curve_sizes.empty() || total != s.control_points.size()) {
    throw SceneError(what + ": the curve sizes do not add up to the control points");
  }
  out += ",\n      \"control_points\": [";
  for (size_t i = 0; i < s.control_points.size(); ++i) {
    const glm::dvec4& cp = s.control_points[i];
    out += i ? ",\n        [" : "\n        [";
    out += number(cp.x, what) + ", " + number(cp.y, what) + ", " + number(cp.z, what) + ", " +
           number(cp.w, what) + "]";
  }
  out += "\n      ],\n      \"curve_sizes\": [";
  for (size_t i = 0; i < s.curve_sizes.size(); ++i) {
    out += (i ? ", " : "") + std::to_string(s.curve_sizes[i]);
  }
  out += "]";
}

/// "attributes": {"vertex_color": [[r, g, b], ...], "face_id": [x, ...]}; nothing without any.
void append_attributes(std::string& out, const Shape& s, const std::string& what) {
  if (s.attributes.empty()) return;
  std::string problem = mesh_attributes_problem(s.attributes, s.positions.size(), s.indices.size());
  if (!problem.empty()) throw SceneError(what + ": " + problem);
  out += ",\n      \"attributes\": {";
  for (size_t k = 0; k < s.attributes.size(); ++k) {
    const MeshAttribute& a = s.attributes[k];
    out += (k ? ",\n        " : "\n        ") + json_string(valid_utf8(a.name)) + ": [";
    const size_t c = size_t(a.channels);
    for (size_t row = 0; row < a.rows(); ++row) {
      out += row ? ", " : "";
      if (c == 1) {
        out += number(a.values[row], what);
      } else {
        out += "[" + number(a.values[row * c], what) + ", " + number(a.values[row * c + 1], what) +
               ", " + number(a.values[row * c + 2], what) + "]";
      }
    }
    out += "]";
  }
  out += "\n      }";
}

/// An SDF grid's "transform" and its "file" (bundle path) or inline "resolution" and "values".
void append_sdf_grid(std::string& out, const Shape& s, const std::string& what) {
  out += ",\n      \"transform\": " + matrix_json(s.to_world, what);
  if (!s.sdf_file.empty()) {
    out += ",\n      \"file\": " + json_string(s.sdf_file);
    return;
  }
  const glm::u32vec3 r = s.sdf_resolution;
  if (uint64_t(r.x) * r.y * r.z != s.sdf_values.size()) {
    throw SceneError(what + ": the SDF grid's values do not match its resolution");
  }
  out += ",\n      \"resolution\": [" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " +
         std::to_string(r.z) + "],\n      \"values\": [";
  for (size_t i = 0; i < s.sdf_values.size(); ++i) {
    out += (i ? ", " : "") + number(double(s.sdf_values[i]), what);
  }
  out += "]";
}

}  // namespace

std::string shape_json(const Shape& s, const std::string& what,
                       const std::vector<Material>& materials, const Names& names) {
  if (s.kind == Shape::Kind::instance) {
    if (s.group >= names.groups.size()) throw SceneError(what + ": group index out of range");
    return "    {\"type\": \"instance\", \"group\": " + json_string(names.groups[s.group]) +
           ",\n      \"transform\": " + matrix_json(s.to_world, what) + "}";
  }
  if (s.material >= materials.size()) throw SceneError(what + ": material index out of range");
  std::string out = "    {";
  if (s.kind == Shape::Kind::sphere) {
    out += "\"type\": \"sphere\", \"center\": " + vec3(s.center, what) +
           ", \"radius\": " + number(s.radius, what) +
           ", \"flip_normals\": " + (s.flip_normals ? "true" : "false");
    if (s.frame != glm::dmat3(1.0)) {
      out += ",\n      \"frame\": [" + vec3(glm::row(s.frame, 0), what) + ", " +
             vec3(glm::row(s.frame, 1), what) + ", " + vec3(glm::row(s.frame, 2), what) + "]";
    }
  } else if (s.kind == Shape::Kind::sdfgrid) {
    out += std::string("\"type\": \"sdfgrid\", \"normals\": ") +
           (s.sdf_normals == SdfNormals::smooth ? "\"smooth\"" : "\"analytic\"");
  } else if (s.kind == Shape::Kind::curves) {
    out += std::string("\"type\": \"curves\", \"basis\": ") +
           (s.curve_basis == CurveBasis::linear ? "\"linear\"" : "\"bspline\"");
  } else {
    out += "\"type\": \"triangles\"";
  }
  out += ", \"material\": " + json_string(names.materials[s.material]);
  if (s.kind == Shape::Kind::sdfgrid) {
    if (s.is_emitter()) throw SceneError(what + ": SDF grids cannot emit light");
    append_sdf_grid(out, s, what);
    return out + "}";
  }
  if (s.kind == Shape::Kind::curves) {
    if (s.is_emitter()) throw SceneError(what + ": curves cannot emit light");
    append_curves(out, s, what);
    return out + "}";
  }
  if (s.bounds_medium() && s.kind != Shape::Kind::triangles && s.kind != Shape::Kind::sphere) {
    throw SceneError(what + ": only triangles and spheres can bound a medium");
  }
  if (s.interior >= 0) out += ", \"interior\": " + medium_name(s.interior, names, what);
  if (s.exterior >= 0) out += ", \"exterior\": " + medium_name(s.exterior, names, what);
  if (s.is_emitter()) {
    out += ",\n      \"emission\": " +
           textured_color({s.emission, s.emission_texture}, names, what + ".emission");
  }
  if (s.is_emitter() && s.two_sided_emission) {
    const Material& m = materials[s.material];
    if (!m.two_sided && !is_glass_kind(m.type)) {
      throw SceneError(what +
                       ": it emits from both sides but its material is one-sided, which "
                       "the native format cannot say");
    }
    out += ", \"two_sided\": true";
  }
  if (s.kind == Shape::Kind::triangles) {
    if (s.indices.empty()) throw SceneError(what + ": no triangles");
    if (!s.normals.empty() && s.normals.size() != s.positions.size()) {
      throw SceneError(what + ": one normal per vertex is needed");
    }
    append_points(out, "vertices", s.positions, what);
    out += ",\n      \"indices\": [";
    for (size_t i = 0; i < s.indices.size(); ++i) {
      const glm::u32vec3& t = s.indices[i];
      out += i ? ",\n        [" : "\n        [";
      out += std::to_string(t.x) + ", " + std::to_string(t.y) + ", " + std::to_string(t.z) + "]";
    }
    out += "\n      ]";
    if (!s.normals.empty()) append_points(out, "normals", s.normals, what);
    if (!s.uvs.empty()) {
      if (s.uvs.size() != s.positions.size()) {
        throw SceneError(what + ": one uv per vertex is needed");
      }
      out += ",\n      \"uvs\": [";
      for (size_t i = 0; i < s.uvs.size(); ++i) {
        out += i ? ", [" : "\n        [";
        out += number(s.uvs[i].x, what) + ", " + number(s.uvs[i].y, what) + "]";
      }
      out += "\n      ]";
    }
    append_attributes(out, s, what);
  }
  return out + "}";
}

}  // namespace tessera::scene_writer
