#include "scene/mesh/mtl_material.h"

#include <cmath>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Reads an MTL colour, each channel finite and in [min, max].
glm::dvec3 checked_rgb(const double (&rgb)[3], double min, double max, const std::string& key,
                       const std::string& context) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(rgb[i]) || rgb[i] < min || rgb[i] > max) {
      std::string range = std::isinf(max)
                              ? ">= " + format_number(min)
                              : "in [" + format_number(min) + ", " + format_number(max) + "]";
      throw SceneError(context + key + "[" + std::to_string(i) + "] must be " + range + " (got " +
                       format_number(rgb[i]) + ")");
    }
  }
  return {rgb[0], rgb[1], rgb[2]};
}

}  // namespace

MtlMaterial convert_mtl_material(const tinyobj::material_t& mtl, const std::string& obj_path) {
  std::string context = obj_path + ": MTL material \"" + printable(mtl.name) + "\": ";
  MtlMaterial out;
  out.material.name = obj_path + ":" + mtl.name;
  if (mtl.illum == 5) {
    out.material.type = MaterialType::mirror;
  } else if (mtl.illum == 7) {
    out.material.type = MaterialType::glass;
    out.material.ior = mtl.ior;
    if (!std::isfinite(mtl.ior) || !(mtl.ior > 0)) {
      throw SceneError(context + "Ni must be > 0 for glass (illum 7) (got " +
                       format_number(mtl.ior) + ")");
    }
  } else {
    out.material.type = MaterialType::diffuse;
    out.material.reflectance.value = checked_rgb(mtl.diffuse, 0, 1, "Kd", context);
  }
  out.emission = checked_rgb(mtl.emission, 0, INFINITY, "Ke", context);
  return out;
}

}  // namespace tessera
