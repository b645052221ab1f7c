// How far a Mitsuba 3 scene's file names may reach (docs/mitsuba.md, "Files, bundles and paths").
#pragma once

namespace tessera {

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

}  // namespace tessera
