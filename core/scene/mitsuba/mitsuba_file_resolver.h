// Where a Mitsuba scene's file names lead: Mitsuba's search path (docs/mitsuba.md, "Files,
// bundles and paths").
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/file_reader.h"
#include "scene/mitsuba/mitsuba_reach.h"

namespace tessera {

/// Mitsuba 3 resolves a relative file name against a list of folders and takes the first that
/// holds the file: the folders of the scene's <path> elements (the latest first), then the scene
/// file's folder. An <include> looks in the including file's folder before them. Tessera does
/// the same inside the bundle: folders are bundle folders ("" for the root, else ending in '/'),
/// and a name may use ".." as long as it stays inside the bundle root.
class MitsubaFileResolver {
 public:
  /// `reader` must outlive this. `scene_folder` is the scene file's bundle folder.
  MitsubaFileResolver(const FileReader& reader, std::string scene_folder, std::string root_name);

  /// Puts `folder` first in the search (a <path>); a confined resolver lets names reach it too.
  void prepend(std::string folder);
  /// From now on a name may only resolve into `folders` or below them, and into the folders
  /// prepended later (MitsubaReach::scene_folders); a name that leaves them is refused before
  /// anything is read.
  void confine_to(std::vector<std::string> folders);
  /// The folders names are confined to, or nullopt when only the bundle root bounds them.
  const std::optional<std::vector<std::string>>& confined_to() const { return confined_to_; }
  /// The folders in search order.
  const std::vector<std::string>& folders() const { return folders_; }
  /// Restores the search path to `folders` (the end of an include: <path>s inside an included
  /// file do not outlive it, as in Mitsuba, whose included files get a copy of the resolver).
  void reset(std::vector<std::string> folders) { folders_ = std::move(folders); }

  /// The bundle path of `filename` as written in property `where`: the first folder (after
  /// `first`, when given) that holds it. Throws SceneError naming `where` and the folders
  /// searched when none does, BundleEscapeError when the name leaves the bundle root, and
  /// SceneError for an absolute name or, when confined, a name that leaves the folders allowed.
  std::string resolve(const MitsubaElement& where, const std::string& filename,
                      const std::optional<std::string>& first = std::nullopt);

  /// The bytes of bundle path `path` (from the last resolve, when it read them).
  std::string read(const std::string& path);

  /// A FileReader that serves the last resolved file from memory and asks the bundle otherwise:
  /// for the mesh readers, so that a file is read once.
  FileReader reader();

  const std::string& root_name() const { return root_name_; }

 private:
  const FileReader& reader_;
  std::vector<std::string> folders_;
  std::string root_name_;
  std::optional<std::vector<std::string>> confined_to_;
  std::string cached_path_;   ///< the last file resolve read
  std::string cached_bytes_;
};

}  // namespace tessera
