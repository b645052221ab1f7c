// Mitsuba 3 XML scenes as Tessera scenes (docs/mitsuba.md).
//
// The importer reads the subset of Mitsuba 3 that Tessera renders the same way, and refuses
// everything else with the element's file, line and what Tessera supports instead: a scene is
// never silently rendered differently from how Mitsuba would render it (up to noise). The
// result is an ordinary Scene; `tessera-worker convert` writes it as native JSON
// (scene_writer.h), which reads back to the same Scene bit for bit. mitsuba/ builds on the
// model, mesh/ and native/; only loader/ builds on it (the layers: scene.h).
#pragma once

#include <string>
#include <string_view>

#include "scene/scene.h"
#include "scene/file_reader.h"
#include "scene/mitsuba/mitsuba_reach.h"

namespace tessera {

/// Parses the Mitsuba 3 XML text of the scene file at bundle path `file_name` (also its name
/// in messages; the files it names are looked up as Mitsuba does, from its folder, and read
/// through `reader` by bundle path). Scene::referenced_files lists the included XML files, the
/// mesh files and the images. `root_name` names the bundle root in messages. An integrator
/// rendered as `path` (ptracer, volpath, direct) is noted on stderr. Throws
/// SceneError("<file>: line <L>: <element>: <what is wrong>"), BundleEscapeError for a path
/// that leaves the bundle root. `reach` bounds the names of included and referenced files
/// (MitsubaReach, mitsuba_reach.h).
Scene parse_mitsuba_scene(std::string_view xml, const std::string& file_name,
                          const FileReader& reader,
                          const std::string& root_name = "the bundle root",
                          MitsubaReach reach = MitsubaReach::bundle);

}  // namespace tessera
