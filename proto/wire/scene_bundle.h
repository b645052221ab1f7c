// A scene bundle: the scene file plus every file it references, content-addressed by the SHA-256
// of a canonical serialization. Shared by the client (builds bundles from disk), the server
// (validates and stores them) and the worker (caches them by hash).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "scene/scene.h"
#include "scene/loader/scene_loader.h"
#include "tessera/v1/job.pb.h"

namespace tessera::wire {

/// A bundle that cannot be used: bad or duplicate paths, missing scene file, corrupt bytes.
/// what() is one line.
class BundleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A validated bundle: every path checked with check_bundle_path (relative, '/'-separated, no
/// "..", no empty component), unique, and the scene file among them.
struct BundleContents {
  std::string scene_file;                     ///< bundle path of the scene file (JSON or XML)
  std::map<std::string, std::string> files;   ///< path -> bytes, sorted by path

  bool operator==(const BundleContents&) const = default;
};

/// Validates a bundle received over the wire. Throws BundleError naming the offending path on
/// absolute paths, "..", empty components, duplicates (after normalisation) or a missing scene
/// file.
BundleContents bundle_from_proto(const v1::SceneBundle& bundle);

v1::SceneBundle bundle_to_proto(const BundleContents& bundle);

/// The canonical serialization the hash is taken over (docs/farm.md, "Scene bundles"): a magic
/// line, the scene file, then every file sorted by path, each length-prefixed (u64
/// little-endian). Equal contents give equal bytes.
std::string canonical_bytes(const BundleContents& bundle);

/// Parses canonical_bytes' output, validating it as bundle_from_proto does. Throws BundleError
/// on truncated or corrupt input.
BundleContents parse_canonical(std::string_view bytes);

/// SHA-256 of canonical_bytes, lowercase hex.
std::string bundle_sha256(const BundleContents& bundle);

/// A FileReader over the bundle: paths are bundle paths, relative to the bundle root, as
/// parse_scene_any asks (the scene file may sit in a folder below the root). Throws SceneError
/// naming the path when the bundle lacks it. The reader keeps its own copy of the files.
FileReader bundle_reader(const BundleContents& bundle);

/// Parses the bundle's scene (parse_scene_any over bundle_reader). Throws SceneError.
Scene parse_bundle_scene(const BundleContents& bundle);

/// Decodes every image the scene uses (bitmap textures, environment maps) through its reader
/// and checks it (check_image_bytes: readable, has pixels, no NaN, infinite or negative value).
/// Throws SceneError "<texture or light origin>: <file>: ..." naming the element that uses it.
/// The server calls it at submit, the CLI before it uploads: a broken image is refused with
/// its name, never met by every worker mid-render.
void check_scene_images(const Scene& scene);

/// Builds the bundle of a scene file on disk: the scene file and every file in
/// Scene::referenced_files, at their paths below the bundle root (load_scene_bundle: `root`
/// when given, else the scene's folder, or for a Mitsuba scene the common folder of everything
/// it names), read through folder_reader (which refuses files outside the root, and symbolic
/// links anywhere below it); the scene file itself must not be a symbolic link either.
/// Validates with load_scene_bundle first (the parsed scene goes to `scene` when not null);
/// throws SceneError on a bad scene. The bundle's scene file is the text load_scene_bundle
/// parsed: with `parameters` (`-D`) written in as <default>s, so the farm reads the same scene.
BundleContents bundle_from_disk(const std::filesystem::path& scene_file, Scene* scene = nullptr,
                                const std::optional<std::filesystem::path>& root = std::nullopt,
                                const MitsubaParameters& parameters = {});

}  // namespace tessera::wire
