// Materials of OBJ meshes, from their MTL files (docs/scenes.md, "OBJ and MTL").
//
// Internal to tessera_core: tinyobjloader's types depend on TINYOBJLOADER_USE_DOUBLE, which
// only targets linking tinyobjloader::tinyobjloader get. Include this from core/scene/*.cpp only.
#pragma once

#include <tiny_obj_loader.h>

#include <glm/vec3.hpp>
#include <string>

#include "scene/scene.h"

#ifndef TINYOBJLOADER_USE_DOUBLE
#error "mtl_material.h needs TINYOBJLOADER_USE_DOUBLE (link tinyobjloader::tinyobjloader)"
#endif

namespace tessera {

/// What Tessera takes from one MTL material.
struct MtlMaterial {
  Material material;       ///< named "<obj path>:<MTL name>", one-sided
  glm::dvec3 emission{0};  ///< Ke, radiance
};

/// Converts an MTL material of the OBJ at bundle path `obj_path`: illum 5 is a mirror, illum 7
/// glass with Ni as its ior (> 0), anything else diffuse with Kd as reflectance (each channel in
/// [0, 1]: a Kd above 1 is refused, not clamped). Ke is the emitted radiance (>= 0). Everything
/// else (Ka, Ks, Ns, Tf, d, map_*, ...) is ignored. Throws SceneError("<obj path>: MTL material
/// \"<name>\": ...") for values out of range.
MtlMaterial convert_mtl_material(const tinyobj::material_t& mtl, const std::string& obj_path);

}  // namespace tessera
