// Reading scene files (scene format v1, docs/scenes.md; Mitsuba 3 XML, docs/mitsuba.md) and
// the bundle of files each one names.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "scene/mitsuba/mitsuba_parameters.h"
#include "scene/scene.h"
#include "scene/scene_error.h"

namespace tessera {

/// Reads a file of the scene's bundle, given its bundle path: relative to the bundle root,
/// already checked ('/'-separated, no "..", no empty component). The scene file's own folder is
/// the root unless the bundle root lies above it (see load_scene_bundle). Returns the bytes;
/// throws SceneError naming the path when it is missing or unreadable.
using FileReader = std::function<std::string(const std::string& bundle_path)>;

/// How far the file names of a Mitsuba 3 scene (<include filename>, a `filename` property) may
/// reach with "..". A <path value="..."> element may always widen the search, as documented
/// in docs/mitsuba.md; this bounds the names looked up along it.
enum class MitsubaReach {
  /// Anywhere inside the bundle root: a root given with --root, or a bundle on the farm (which
  /// holds only what its client sent).
  bundle,
  /// Only the scene file's folder and the folders of its <path> elements, and what lies below
  /// them: a scene read from disk without --root, whose default root widens as its paths climb.
  scene_folders,
};

/// A path that leaves the bundle root: `levels` more folders above the root would hold it.
/// load_scene_bundle widens a default root by that much and reads the scene again; with a
/// fixed root (--root DIR, a bundle on the farm) it is a refusal like any SceneError.
class BundleEscapeError : public SceneError {
 public:
  BundleEscapeError(const std::string& message, int levels)
      : SceneError(message), levels_(levels) {}
  int levels() const { return levels_; }

 private:
  int levels_;
};

/// Parses scene JSON text. `reader` supplies referenced files (meshes, MTL files). Throws
/// SceneError whose message starts with the JSON path of the offending value.
Scene parse_scene(std::string_view json_text, const FileReader& reader);

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

/// A FileReader over a folder on disk, refusing anything that resolves outside it and symbolic
/// links anywhere below it.
FileReader folder_reader(const std::filesystem::path& folder);

/// Checks a relative path as a bundle path; throws SceneError("<context>: ...") when absolute,
/// empty, or containing ".." or empty components. Returns it normalised with '/' separators.
std::string check_bundle_path(const std::string& path, const std::string& context);

/// The bundle path of `path` as written in a scene file (relative; '\\' or '/' separators; "."
/// and ".." components allowed) read from bundle folder `folder` ("" for the root, else ending
/// in '/'), normalised. Throws SceneError("<context>: ...") for an empty or absolute path, an
/// empty component or no file name, and BundleEscapeError("<context>: ... leaves the bundle
/// root (<root_name>) ...") when ".." climbs above the root.
std::string join_bundle_path(const std::string& folder, const std::string& path,
                             const std::string& context,
                             const std::string& root_name = "the bundle root");

}  // namespace tessera
