#include "scene/mitsuba/mitsuba_medium.h"

#include <cmath>
#include <set>

#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/message_text.h"
#include "scene/native/medium_parser.h"

namespace tessera {
namespace {

/// A medium's sigma_t or albedo: a constant (<float>, <rgb>, <spectrum>, or a constvolume,
/// which Mitsuba's props.volume makes of each of them), or a gridvolume (heterogeneous only).
TexturedColor read_medium_value(MitsubaPlugin& plugin, std::string_view name, double fallback,
                                MitsubaColorRole role, bool heterogeneous, MitsubaTextures& textures) {
  if (std::optional<MitsubaObject> object = plugin.take_named_object(name)) {
    if (object->element->tag != "volume") {
      fail_at(*object->written, "a medium's " + std::string(name) +
                                    " is a <float>, an <rgb>, a <spectrum> or a <volume> "
                                    "(constvolume or gridvolume)");
    }
    const int32_t index = textures.of_volume(*object->element);
    const Texture& volume = textures.at(index);
    // A constvolume is its value everywhere; a heterogeneous medium is empty outside its
    // to_world's box, so that one stays a texture.
    if (!volume.grid && (!heterogeneous || volume.volume_to_world == glm::dmat4(1.0))) {
      return {volume.value, -1};
    }
    if (!heterogeneous && name == "sigma_t") {
      fail_at(*object->written,
              "a homogeneous medium's sigma_t is constant (Mitsuba samples its free flights as "
              "if it were); write the medium as heterogeneous");
    }
    return {glm::dvec3(1), index};
  }
  std::optional<glm::dvec3> value = plugin.take_color(name, role);
  return {value.value_or(glm::dvec3(fallback)), -1};
}

void read_phase(MitsubaPlugin& plugin, const MitsubaIds& ids, Medium& m) {
  std::vector<MitsubaObject> phases = plugin.take_objects("phase");
  if (phases.empty()) return;  // Mitsuba's default: isotropic
  if (phases.size() > 1) fail_at(*phases[1].written, "a medium has one phase function");
  const MitsubaElement& element = *phases.front().element;
  MitsubaPlugin phase(element, ids);
  if (phase.type() == "hg") {
    m.phase = PhaseKind::hg;
    m.g = phase.take_float("g").value_or(0.8);
    if (!(std::abs(m.g) < 1)) {
      fail_at(*phase.property("g"), "must be in (-1, 1) (got " + format_number(m.g) + ")");
    }
  } else if (phase.type() != "isotropic") {
    fail_at(element, "unsupported phase function (Tessera reads isotropic and hg)");
  }
  phase.finish();
}

}  // namespace

int32_t MitsubaMedia::of(const MitsubaElement& element) {
  auto it = index_of_.find(&element);
  if (it != index_of_.end()) return it->second;
  Medium m = read(element);
  const std::string* id = element.attribute("id");
  std::string name = id && !id->empty() ? *id : "medium (" + element.file + " line " + std::to_string(element.line) + ")";
  std::set<std::string> used;
  for (const Medium& other : media_) used.insert(other.name);
  std::string unique = name;
  for (int k = 2; used.count(unique); ++k) unique = name + " #" + std::to_string(k);
  m.name = unique;
  media_.push_back(std::move(m));
  const int32_t index = int32_t(media_.size() - 1);
  index_of_[&element] = index;
  return index;
}

std::vector<Medium> MitsubaMedia::take() {
  std::vector<Medium> result = std::move(media_);
  media_.clear();
  index_of_.clear();
  return result;
}

Medium MitsubaMedia::read(const MitsubaElement& element) {
  MitsubaPlugin plugin(element, ids_);
  Medium m;
  m.origin = element.where();
  if (plugin.type() == "heterogeneous") {
    m.kind = MediumKind::heterogeneous;
  } else if (plugin.type() != "homogeneous") {
    fail_at(element, "unsupported medium (Tessera reads homogeneous and heterogeneous)");
  }
  const bool heterogeneous = m.kind == MediumKind::heterogeneous;
  m.sigma_t = read_medium_value(plugin, "sigma_t", 1.0, MitsubaColorRole::unbounded, heterogeneous, textures_);
  m.albedo = read_medium_value(plugin, "albedo", 0.75, MitsubaColorRole::reflectance, heterogeneous, textures_);
  m.scale = plugin.take_float("scale").value_or(1.0);
  m.sample_emitters = plugin.take_boolean("sample_emitters").value_or(true);
  read_phase(plugin, ids_, m);
  if (std::optional<bool> spectral = plugin.take_boolean("has_spectral_extinction"); spectral && !*spectral) {
    // Mitsuba then weighs every channel by the sampled channel's extinction: its image is the
    // medium's only when sigma_t is grey.
    const glm::dvec3 s = m.sigma_t.value;
    if (!m.sigma_t.is_constant() || s.x != s.y || s.x != s.z) {
      fail_at(*plugin.property("has_spectral_extinction"),
              "false with a sigma_t that is not one grey constant: Mitsuba then renders every "
              "channel with the sampled channel's extinction, which Tessera does not reproduce "
              "(write true or leave it out)");
    }
  }
  // The grids were checked when they were read (MitsubaTextures::of_volume).
  const std::string problem = medium_problem(m, nullptr);
  if (!problem.empty()) fail_at(element, problem);
  plugin.finish();
  return m;
}

}  // namespace tessera
