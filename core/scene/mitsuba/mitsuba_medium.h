// Mitsuba's participating media: <medium> (homogeneous, heterogeneous) with its <phase>
// (docs/mitsuba.md, "Media").
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// The scene's media, read on first use (a medium named by several shapes through <ref> is one
/// Medium), with Mitsuba 3's parameters, defaults and meaning (src/media/homogeneous.cpp,
/// heterogeneous.cpp, src/phase/hg.cpp):
/// - `homogeneous`: sigma_t (default 1) and albedo (default 0.75), each a <float>, <rgb>,
///   <spectrum> (as Mitsuba's RGB variants read it) or a constvolume, the albedo also a
///   gridvolume; scale (1);
/// - `heterogeneous`: the same, each also a gridvolume (a .vol grid over its to_world);
/// - both: one <phase> (isotropic, the default, or hg with g, default 0.8, |g| < 1),
///   sample_emitters (true), has_spectral_extinction (true; false only with a grey sigma_t,
///   which is the one case where Mitsuba's image does not depend on it).
/// Anything else is refused with SceneError naming the element.
class MitsubaMedia {
 public:
  MitsubaMedia(const MitsubaIds& ids, MitsubaTextures& textures) : ids_(ids), textures_(textures) {}

  /// The index in Scene::media of <medium> element `medium`.
  int32_t of(const MitsubaElement& medium);
  /// The media in index order; the table is empty afterwards.
  std::vector<Medium> take();

 private:
  Medium read(const MitsubaElement& element);

  const MitsubaIds& ids_;
  MitsubaTextures& textures_;
  std::vector<Medium> media_;
  std::map<const MitsubaElement*, int32_t> index_of_;
};

}  // namespace tessera
