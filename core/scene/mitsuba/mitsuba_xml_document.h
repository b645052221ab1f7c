// A Mitsuba 3 XML scene file read into a tree of elements (docs/mitsuba.md): <include>s spliced
// in, <default> parameters substituted, and every element knowing the file and line it came
// from, so that each later error can name them.
//
// This layer knows XML and Mitsuba's preprocessing only; what the elements mean is read by the
// plugin readers (mitsuba_sensor.h, mitsuba_bsdf.h, mitsuba_shape.h, ...).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/file_reader.h"
#include "scene/mitsuba/mitsuba_reach.h"

namespace tessera {

/// One XML element after preprocessing.
struct MitsubaElement {
  std::string tag;
  /// In file order, with `$name` parameters substituted and `\$` unescaped.
  std::vector<std::pair<std::string, std::string>> attributes;
  /// Child elements in file order, included files spliced in; text and comments are dropped
  /// (Mitsuba ignores them too).
  std::vector<MitsubaElement> children;
  std::string file;    ///< the file it is in, for messages (the scene file's name as given)
  std::string folder;  ///< bundle path of that file's folder: "" at the root, else "a/b/"
  int line = 0;        ///< 1-based line of its start tag

  /// The value of attribute `name`, or nullptr when the element has none.
  const std::string* attribute(std::string_view name) const;
  /// The start tag with its identifying attributes, for messages: `<bsdf type="diffuse"
  /// id="white">`, `<float name="fov">`.
  std::string label() const;
  /// "<file>: line <L>: <label>", the prefix of every message about this element.
  std::string where() const;
};

/// Throws SceneError("<file>: line <L>: <label>: <message>").
[[noreturn]] void fail_at(const MitsubaElement& element, std::string_view message);

/// Mitsuba scenes are read with bounds, since a scene comes from users (and the fuzzer).
inline constexpr int kMaxMitsubaIncludeDepth = 16;        ///< nested <include>s
inline constexpr int kMaxMitsubaElementDepth = 64;        ///< nested elements
inline constexpr size_t kMaxMitsubaElements = 1'000'000;  ///< elements after includes

struct MitsubaDocument {
  MitsubaElement scene;                 ///< the root <scene> element
  std::vector<std::string> files_read;  ///< bundle paths of the included files, each once
  /// Where the scene's file names are looked for, in order: the folders of its <path> elements
  /// (the latest first), then the scene file's folder (MitsubaFileResolver).
  std::vector<std::string> search_folders;
  /// With MitsubaReach::scene_folders: the folders file names must stay in (the scene file's
  /// folder and every <path> folder, included files' too); nullopt with MitsubaReach::bundle.
  std::optional<std::vector<std::string>> confined_to;
};

/// Reads the XML text of the scene file at bundle path `file_name`.
///
/// - The root must be `<scene version="3.x.y">` (or "2.x.y", which Mitsuba 3 reads alike).
/// - `<default name="n" value="v"/>` declares parameter `n` unless it exists already (the first
///   declaration wins, as in Mitsuba). Every attribute of every later element, in document
///   order, has `$n` replaced by `v` (longer names first, so `$spp2` is not read as `$spp`
///   followed by "2"); `\$` is a literal dollar; a `$name` left undeclared is an error.
/// - `<path value="dir"/>`, a child of the root: `dir`, relative to the folder of the file that
///   names it, is searched first for the files named after it (MitsubaFileResolver).
/// - `<include filename="f.xml"/>` reads `f.xml` through `reader`, looked for in the folder of
///   the file that names it, then along the search path; a root `<scene>` there contributes its
///   children, any other root element itself. Parameters are shared with included files; the
///   <path>s of an included file end with it. Includes nest at most kMaxMitsubaIncludeDepth
///   deep and never in a cycle.
/// `root_name` names the bundle root in messages about paths that leave it. With `reach`
/// MitsubaReach::scene_folders an included file must lie in the scene file's folder or a
/// <path> folder (or below one).
///
/// Throws SceneError("<file>: line <L>: ...") for malformed XML and for every rule above, and
/// BundleEscapeError for a path that leaves the bundle root.
MitsubaDocument read_mitsuba_document(std::string_view xml, const std::string& file_name,
                                      const FileReader& reader,
                                      const std::string& root_name = "the bundle root",
                                      MitsubaReach reach = MitsubaReach::bundle);

}  // namespace tessera
