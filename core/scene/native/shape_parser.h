// One element of the "shapes" array of a scene file (docs/scenes.md, "`shapes`").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/native/material_table.h"
#include "scene/native/medium_parser.h"
#include "scene/native/texture_parser.h"
#include "scene/scene.h"
#include "scene/file_reader.h"

namespace tessera {

/// What parsing shapes needs beyond the shape itself.
struct ShapeContext {
  MaterialTable& materials;                    ///< declared materials; derived ones are added
  const FileReader& reader;                    ///< mesh and MTL files
  std::vector<std::string>& referenced_files;  ///< files read, each once, in order of first use
  const TextureNames& textures;                ///< for textured emission
  /// Group name -> index into Scene::groups, for "instance" shapes; nullptr inside a group
  /// (groups do not nest).
  const std::map<std::string, uint32_t>* groups = nullptr;
  /// The scene's media, for "interior" and "exterior"; nullptr inside a group (a group's
  /// shapes bound no media).
  const MediumNames* media = nullptr;
};

/// Parses one shape object (its path, e.g. "shapes[3]", is `value.path()`) and appends its
/// Shapes in world space: one, or one per material for an OBJ mesh using its MTL materials.
///
/// An "instance" shape ({"group": name, "transform"}) becomes one Shape::Kind::instance;
/// "curves" and "sdfgrid" shapes are parsed by curve_shape.h and sdfgrid_shape.h.
/// Otherwise applies, in order: the geometry of its "type" (quad, sphere, triangles, box,
/// tetrahedron, mesh); "transform"; "flip_normals"; degenerate triangles (an error for
/// explicit geometry, dropped and counted for mesh files); the material ("material", else the file's MTL
/// material, else "(black)" for lights), made two-sided by "two_sided"; the light
/// ("emission", or "power" over the world-space area of all its parts, else the MTL's Ke).
/// Throws SceneError whose message starts with the JSON path of what is wrong.
void parse_shape(const JsonValue& value, ShapeContext& context, std::vector<Shape>& shapes);

}  // namespace tessera
