// Reading scene files (scene format v1, docs/scenes.md; Mitsuba 3 XML, docs/mitsuba.md) and
// the bundle of files each one names. loader/ is the top layer of core/scene/ (scene.h): it
// dispatches to native/ and mitsuba/, and nothing in core/scene/ includes it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "scene/bundle_path.h"
#include "scene/file_reader.h"
#include "scene/mitsuba/mitsuba_parameters.h"
#include "scene/mitsuba/mitsuba_reach.h"
#include "scene/native/scene_parser.h"
#include "scene/scene.h"
#include "scene/scene_error.h"

namespace tessera {

/// A scene file on disk read with its bundle (docs/mitsuba.md, "Files, bundles and paths").
struct SceneOnDisk {
  Scene scene;                 ///< Scene::referenced_files are bundle paths below `root`
  std::filesystem::path root;  ///< the bundle root: absolute, canonical
  std::string scene_path;      ///< the scene file's bundle path below `root`
  /// The text that was parsed: the scene file's bytes, with the `-D` parameters written in
  /// (with_mitsuba_parameters) when there are any. A bundle carries this text as the scene file.
  std::string scene_text;
};

/// Loads a scene file from disk with its bundle. The bundle root is `root` when given (the
/// scene file must be inside it), else the scene file's folder, widened for a Mitsuba scene to
/// the common folder of everything it names: a <path> may climb with `..` as far as it likes,
/// an <include> or a file name only within the scene's folder and its <path> folders
/// (MitsubaReach::scene_folders). A given root allows any path inside it. Files are read through folder_reader(root): absolute paths, paths leaving the root
/// and symbolic links below it are refused, naming the file, line and root. A file whose name
/// ends in ".xml" (any case) is read as a Mitsuba 3 scene (docs/mitsuba.md), any other as scene
/// format v1 (whose paths are relative to the scene's folder, without "..").
/// `parameters` (`-D name=value`) override the Mitsuba scene's <default>s
/// (with_mitsuba_parameters); a native scene given any is refused ("-D sets parameters of
/// Mitsuba 3 XML scenes").
SceneOnDisk load_scene_bundle(const std::filesystem::path& scene_file,
                              const std::optional<std::filesystem::path>& root = std::nullopt,
                              const MitsubaParameters& parameters = {});

/// load_scene_bundle(scene_file, root, parameters).scene.
Scene load_scene_file(const std::filesystem::path& scene_file,
                      const std::optional<std::filesystem::path>& root = std::nullopt,
                      const MitsubaParameters& parameters = {});

/// Parses the text of a scene file at bundle path `file_name` (the root of its bundle, or a
/// folder below it): a Mitsuba 3 XML scene when the name ends in ".xml" (any case), scene format
/// v1 otherwise. `reader` supplies the bundle's files; `root_name` names the bundle root in
/// messages; `reach` bounds a Mitsuba scene's file names (MitsubaReach). For callers that hold a
/// bundle's bytes rather than files on disk, such as the farm.
Scene parse_scene_any(const std::string& file_name, std::string_view text,
                      const FileReader& reader,
                      const std::string& root_name = "the bundle root",
                      MitsubaReach reach = MitsubaReach::bundle);

}  // namespace tessera
