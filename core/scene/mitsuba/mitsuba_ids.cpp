#include "scene/mitsuba/mitsuba_ids.h"

#include <array>
#include <string_view>

#include "scene/message_text.h"

namespace tessera {

bool is_mitsuba_object_tag(const std::string& tag) {
  static constexpr std::array<std::string_view, 13> kObjects = {
      "scene",   "bsdf",       "emitter", "shape",  "sensor", "film",  "sampler",
      "rfilter", "integrator", "texture", "medium", "phase",  "volume"};
  for (std::string_view object : kObjects) {
    if (tag == object) return true;
  }
  return false;
}

MitsubaIds::MitsubaIds(const MitsubaElement& scene) { collect(scene); }

void MitsubaIds::collect(const MitsubaElement& element) {
  const std::string* id = element.attribute("id");
  if (id && !id->empty() && is_mitsuba_object_tag(element.tag)) {
    auto [it, added] = by_id_.try_emplace(*id, &element);
    if (!added) {
      fail_at(element, "duplicate id \"" + printable(*id) + "\" (first at " +
                           printable(it->second->file) + " line " +
                           std::to_string(it->second->line) + ")");
    }
  }
  for (const MitsubaElement& child : element.children) collect(child);
}

const MitsubaElement& MitsubaIds::resolve(const MitsubaElement& ref) const {
  const std::string* id = ref.attribute("id");
  if (!id) fail_at(ref, "missing attribute \"id\"");
  auto it = by_id_.find(*id);
  if (it == by_id_.end()) fail_at(ref, "no object has id \"" + printable(*id) + "\"");
  return *it->second;
}

}  // namespace tessera
