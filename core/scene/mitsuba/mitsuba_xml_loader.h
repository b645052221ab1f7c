// Mitsuba 3 XML scenes as Tessera scenes (docs/mitsuba.md).
//
// The importer reads the subset of Mitsuba 3 that Tessera renders the same way, and refuses
// everything else with the element's file, line and what Tessera supports instead: a scene is
// never silently rendered differently from how Mitsuba would render it (up to noise). The
// result is an ordinary Scene; `tessera-worker convert` writes it as native JSON
// (scene_writer.h), which reads back to the same Scene bit for bit.
#pragma once

#include <string>
#include <string_view>

#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace tessera {

/// Parses the Mitsuba 3 XML text of the scene file `file_name` (its name at the root of its
/// bundle, for messages; the files it names are read through `reader` relative to the bundle
/// root). Scene::referenced_files lists the included XML files and the mesh files. Throws
/// SceneError("<file>: line <L>: <element>: <what is wrong>").
Scene parse_mitsuba_scene(std::string_view xml, const std::string& file_name,
                          const FileReader& reader);

}  // namespace tessera
