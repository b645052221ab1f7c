// Mitsuba shapes as Tessera shapes in world space (docs/mitsuba.md, "Shapes").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_bsdf.h"
#include "scene/mitsuba/mitsuba_file_resolver.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_medium.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// What reading shapes needs beyond the shape element; every member outlives the reading.
struct MitsubaShapeContext {
  const MitsubaIds& ids;
  MitsubaFileResolver& files;                  ///< mesh files, looked up as Mitsuba does
  MitsubaMaterials& materials;                 ///< BSDFs become materials on first use
  MitsubaTextures& textures;                   ///< textured area emitters
  std::vector<std::string>& referenced_files;  ///< mesh files read, each once
  std::vector<ShapeGroup>& groups;             ///< shape groups, read on first use
  /// The scene's lights: a point, spot, directional or projector emitter written inside a
  /// shape joins them, as in Mitsuba (read_mitsuba_shape).
  std::vector<Light>& lights;
  MitsubaMedia& media;  ///< <medium name="interior" / "exterior"> of shapes, read on first use
  std::map<const MitsubaElement*, uint32_t> group_index{};
};

/// Reads one <shape> element (its <medium> or <ref> named interior or exterior, if any, sets
/// Shape::interior / exterior; curves, SDF grids and a shapegroup's shapes bound no medium): `obj` and `ply` (filename looked up as Mitsuba does,
/// face_normals; an OBJ's MTL files are not read, as in Mitsuba), `rectangle`, `cube`, `disk`
/// (tessellated, with Mitsuba's uv parametrisation) and `sphere` (center, radius; it stays
/// exact, so its to_world must be a similarity), each with to_world and flip_normals, at most
/// one BSDF (Mitsuba's default diffuse 0.5 without one, black with an emitter) and at most one
/// emitter: an area emitter makes the shape glow; a point, spot, directional or projector
/// emitter is a light of the scene as Mitsuba reads it (appended to context.lights; it keeps its
/// own to_world and the shape does not glow; constant and envmap are refused); and
/// `instance`, which places a `shapegroup` (named through <ref>) by its to_world; `sdfgrid` (a
/// `.vol` file, normals, to_world; no emitter, no flip_normals: sdfgrid_shape.h). Mesh files
/// without normals get Mitsuba's vertex normals unless face_normals is true. Degenerate
/// triangles of mesh files are dropped and counted (a mesh file whose faces are all degenerate
/// gives an empty shape, see mitsuba_shape_is_empty; as a light it is refused); built-in shapes
/// made degenerate by to_world are an error. Shape::origin is the element's place, "<file>: line <L>: <shape ...>". Throws
/// SceneError naming the element for anything else (`shapegroup` is read by
/// read_mitsuba_shape_group).
Shape read_mitsuba_shape(const MitsubaElement& shape, MitsubaShapeContext& context);

/// The index in context.groups of <shape type="shapegroup"> element `group`, read on first use:
/// its shapes (not emitters, instances or groups) in the group's own space.
uint32_t read_mitsuba_shape_group(const MitsubaElement& group, MitsubaShapeContext& context);

/// True for a mesh shape left without triangles (every face of its file degenerate, as in the
/// Mitsuba 3 version of Bitterli's staircase): Mitsuba loads it and no ray ever hits it, so the
/// scene leaves it out, after note_empty_mitsuba_shape says so on stderr.
bool mitsuba_shape_is_empty(const Shape& shape);
void note_empty_mitsuba_shape(const Shape& shape);

}  // namespace tessera
