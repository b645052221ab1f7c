// The `id`s of a Mitsuba scene and the <ref id="..."> elements that point to them.
#pragma once

#include <map>
#include <string>

#include "scene/mitsuba/mitsuba_xml_document.h"

namespace tessera {

/// Tags of Mitsuba's object (plugin) elements, which may carry an id.
bool is_mitsuba_object_tag(const std::string& tag);

/// Every object element with an `id`, anywhere in the scene (a <ref> may name an object declared
/// later in the file, as Mitsuba 3 allows).
class MitsubaIds {
 public:
  /// Collects the ids under `scene`; throws SceneError at the second of two objects with the
  /// same id.
  explicit MitsubaIds(const MitsubaElement& scene);

  /// The object a <ref id="..."> element points to; throws SceneError naming the <ref> when no
  /// object has that id.
  const MitsubaElement& resolve(const MitsubaElement& ref) const;

 private:
  void collect(const MitsubaElement& element);

  std::map<std::string, const MitsubaElement*> by_id_;
};

}  // namespace tessera
