#include "scene/mesh_attribute.h"

#include <cmath>

namespace tessera {

const MeshAttribute* find_mesh_attribute(const std::vector<MeshAttribute>& attributes,
                                         std::string_view name) {
  for (const MeshAttribute& a : attributes) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

std::string mesh_attributes_problem(const std::vector<MeshAttribute>& attributes,
                                    size_t vertices, size_t triangles) {
  for (size_t i = 0; i < attributes.size(); ++i) {
    const MeshAttribute& a = attributes[i];
    const std::string what = "attribute \"" + a.name + "\"";
    if (!a.per_vertex() && !MeshAttribute::is_face_attribute_name(a.name)) {
      return what + ": the name must start with \"vertex_\" or \"face_\"";
    }
    for (size_t j = 0; j < i; ++j) {
      if (attributes[j].name == a.name) return what + " is given twice";
    }
    if (a.channels != 1 && a.channels != 3) {
      return what + ": 1 or 3 channels (got " + std::to_string(a.channels) + ")";
    }
    const size_t rows = a.per_vertex() ? vertices : triangles;
    if (a.values.size() != rows * size_t(a.channels)) {
      return what + ": " + std::to_string(a.values.size()) + " values for " +
             std::to_string(rows) + (a.per_vertex() ? " vertices" : " triangles") + " of " +
             std::to_string(a.channels) + " channel" + (a.channels == 1 ? "" : "s");
    }
    for (float v : a.values) {
      if (!std::isfinite(v)) return what + ": a value is not a finite number";
    }
  }
  return "";
}

}  // namespace tessera
