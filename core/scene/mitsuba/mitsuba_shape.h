// Mitsuba shapes as Tessera shapes in world space (docs/mitsuba.md, "Shapes").
#pragma once

#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_bsdf.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace tessera {

/// What reading shapes needs beyond the shape element.
struct MitsubaShapeContext {
  const MitsubaIds& ids;
  const FileReader& reader;                    ///< mesh files, by bundle path
  MitsubaMaterials& materials;                 ///< BSDFs become materials on first use
  std::vector<std::string>& referenced_files;  ///< mesh files read, each once
};

/// Reads one <shape> element: `obj` and `ply` (filename relative to the folder of the XML file
/// that names it, face_normals; an OBJ's MTL files are not read, as in Mitsuba), `rectangle`,
/// `cube`, `disk` (tessellated) and `sphere` (center, radius; it stays exact, so its to_world
/// must be a similarity), each with to_world and flip_normals, at most one BSDF (Mitsuba's
/// default diffuse 0.5 without one) and at most one area emitter (radiance). Mesh files without
/// normals get Mitsuba's vertex normals unless face_normals is true. Degenerate triangles of
/// mesh files are dropped and counted; built-in shapes made degenerate by to_world are an error.
/// Shape::origin is the element's place, "<file>: line <L>: <shape ...>". Throws SceneError
/// naming the element for anything else.
Shape read_mitsuba_shape(const MitsubaElement& shape, MitsubaShapeContext& context);

}  // namespace tessera
