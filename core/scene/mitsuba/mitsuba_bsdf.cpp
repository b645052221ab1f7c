// MitsubaMaterials (mitsuba_bsdf.h): the table of a scene's materials, and the BSDFs around
// others (twosided, blendbsdf, mask, bumpmap, normalmap) or none (null).
#include "scene/mitsuba/mitsuba_bsdf.h"

#include <algorithm>
#include <cmath>

#include "scene/mitsuba/mitsuba_hair.h"
#include "scene/mitsuba/mitsuba_surface_bsdfs.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/message_text.h"

namespace tessera {
namespace {

constexpr const char* kSupported =
    "Tessera supports diffuse, conductor, roughconductor, dielectric, roughdielectric, "
    "thindielectric, plastic, roughplastic, pplastic, principled, principledthin, polarizer, "
    "hair, blendbsdf, null, "
    "twosided, mask, bumpmap and normalmap";

/// Mitsuba's null BSDF (src/bsdfs/null.cpp): every hit is a null interaction, the path goes on
/// straight with weight 1, and the surface reflects nothing; the shape still blocks shadow rays
/// and, under the path integrator, each passage is a vertex (path.cpp counts every hit). That
/// is exactly a mask of opacity 0 (integrator.cpp's null interaction), around a black diffuse
/// BSDF that no path ever evaluates.
Material read_null() {
  Material m;
  m.type = MaterialType::diffuse;
  m.reflectance = TexturedColor{glm::dvec3(0), -1};
  m.opacity = TexturedFloat{0, -1};
  return m;
}

/// The opacity of a mask of `outer` opacity around a BSDF of `inner` opacity (a null BSDF's 0,
/// or a nested mask's): Mitsuba's masks nest as a product (a hit is opaque when each decides
/// so). A constant inner scales the outer one (TexturedFloat is value * texture); two textures
/// are refused.
TexturedFloat nested_opacity(TexturedFloat outer, const TexturedFloat& inner,
                             const MitsubaElement& where) {
  if (inner.is_constant()) {
    outer.value *= inner.value;
    return outer;
  }
  if (outer.is_constant()) {
    TexturedFloat product = inner;
    product.value *= outer.value;
    return product;
  }
  fail_at(where, "a textured mask around another textured mask: Tessera takes one opacity "
                 "texture per material");
}

/// The one BSDF nested in a wrapper (twosided, mask, bumpmap, normalmap).
const MitsubaElement& single_nested(MitsubaPlugin& plugin) {
  std::vector<MitsubaObject> nested = plugin.take_objects("bsdf");
  if (nested.size() != 1) {
    fail_at(nested.empty() ? plugin.element() : *nested[1].written,
            nested.empty() ? "needs one nested BSDF" : "takes one nested BSDF");
  }
  return *nested.front().element;
}

}  // namespace

Material MitsubaMaterials::read_twosided(MitsubaPlugin& plugin) {
  std::vector<MitsubaObject> nested = plugin.take_objects("bsdf");
  if (nested.empty() || nested.size() > 2) {
    fail_at(nested.empty() ? plugin.element() : *nested[2].written,
            "takes one nested BSDF (both sides alike) or two (front, back)");
  }
  std::vector<Material> sides;
  for (const MitsubaObject& side : nested) {
    const std::string* type = side.element->attribute("type");
    Material m = read(*side.element);
    if (type && *type == "twosided") {
      // Mitsuba's twosided turns wi to the front side before it calls a nested BSDF, so a
      // twosided inside a twosided (as in the Mitsuba 3 versions of Bitterli's car scenes) only
      // ever shows its front BSDF: twosided(twosided(A, B)) renders as twosided(A). The inner
      // back BSDF was read (and checked) but is never seen.
      m.back = -1;
    }
    if (m.transmits()) {
      fail_at(*side.written,
              "twosided takes only BSDFs that do not transmit light (as in Mitsuba); a "
              "dielectric (or a principled BSDF with spec_trans) is two-sided already");
    }
    if (!m.opacity.is_constant() || m.opacity.value != 1) {
      // Mitsuba's mask and null BSDFs have a null (transmission) component, which its
      // twosided refuses ("Only materials without a transmission component can be nested").
      fail_at(*side.written,
              "twosided takes only BSDFs that do not transmit light (as in Mitsuba); a mask or "
              "null BSDF lets light through both sides already: put the mask around the "
              "twosided");
    }
    m.two_sided = true;
    sides.push_back(std::move(m));
  }
  if (sides.size() == 2) {
    sides[0].back = int32_t(add(std::move(sides[1]), *nested[1].element));
  }
  return sides[0];
}

Material MitsubaMaterials::read_blend(MitsubaPlugin& plugin) {
  if (!plugin.has("weight")) fail_at(plugin.element(), "needs a weight (float or texture), as in Mitsuba");
  Material m;
  m.type = MaterialType::blend;
  m.blend_weight = read_textured_float(plugin, "weight", 0.5, textures_);
  if (m.blend_weight.is_constant()) {
    m.blend_weight.value = std::clamp(m.blend_weight.value, 0.0, 1.0);  // Mitsuba clamps it
  }
  std::vector<MitsubaObject> nested = plugin.take_objects("bsdf");
  if (nested.size() != 2) {
    fail_at(nested.size() > 2 ? *nested[2].written : plugin.element(),
            "takes two nested BSDFs, as in Mitsuba");
  }
  // Blender exports (mitsuba-blender's Mix Shader) blend two twosided BSDFs. Mitsuba's blend
  // weighs its two nested BSDFs' values and samples; each twosided turns wi to the front side
  // alike, so blend(twosided(A), twosided(B)) is twosided(blend(A, B)) exactly.
  const MitsubaObject* one_sided = nullptr;
  const MitsubaObject* two_sided = nullptr;
  for (const MitsubaObject& n : nested) {
    Material inner = read(*n.element);
    const std::string* type = n.element->attribute("type");
    if (type && *type == "twosided" && inner.back < 0) {
      inner.two_sided = false;
      two_sided = &n;
    } else {
      one_sided = &n;
    }
    if (inner.two_sided || inner.back >= 0 || !inner.opacity.is_constant() ||
        inner.opacity.value != 1 || inner.normal_map >= 0 || inner.bump_map >= 0) {
      fail_at(*n.written,
              "Tessera blends BSDFs without twosided, mask, null, bumpmap or normalmap inside; "
              "put those around the blendbsdf");
    }
    m.blend.push_back(std::move(inner));
  }
  if (two_sided && one_sided) {
    fail_at(*two_sided->written,
            "a blend of a twosided and a one-sided BSDF (" + one_sided->written->where() +
                "): Tessera makes a blend two-sided as a whole, so both or neither must be "
                "twosided (or put the twosided around the blendbsdf)");
  }
  m.two_sided = two_sided != nullptr;
  return m;
}

Material MitsubaMaterials::read_wrapper(MitsubaPlugin& plugin) {
  if (plugin.type() == "mask") {
    TexturedFloat opacity = read_textured_float(plugin, "opacity", 0.5, textures_);
    if (opacity.is_constant() && !(opacity.value >= 0 && opacity.value <= 1)) {
      fail_at(*plugin.property("opacity"),
              "must be in [0, 1] (got " + format_number(opacity.value) + ")");
    }
    Material m = read(single_nested(plugin));
    m.opacity = nested_opacity(opacity, m.opacity, plugin.element());
    return m;
  }
  if (plugin.type() == "bumpmap") {
    std::vector<MitsubaObject> height = plugin.take_objects("texture");
    if (height.size() != 1) {
      fail_at(plugin.element(), "takes one nested <texture>, the height field");
    }
    double scale = plugin.take_float("scale").value_or(1.0);
    Material m = read(single_nested(plugin));
    if (m.bump_map >= 0 || m.normal_map >= 0) {
      fail_at(plugin.element(), "Tessera applies one bumpmap or normalmap per material");
    }
    m.bump_map = textures_.of(*height.front().element);
    m.bump_scale = scale;
    return m;
  }
  // normalmap
  std::optional<MitsubaObject> normals = plugin.take_named_object("normalmap");
  if (!normals) {
    fail_at(plugin.element(), "needs <texture type=\"bitmap\" name=\"normalmap\"> (raw)");
  }
  Material m = read(single_nested(plugin));
  if (m.bump_map >= 0 || m.normal_map >= 0) {
    fail_at(plugin.element(), "Tessera applies one bumpmap or normalmap per material");
  }
  m.normal_map = textures_.of(*normals->element);
  return m;
}

namespace {

/// Mitsuba's measured_polarized (src/bsdfs/measured_polarized.cpp) interpolates a measured
/// polarimetric BRDF (a .pbsdf tensor file of Baek et al. 2020) over five wavelength bands. Its
/// RGB variants throw unless `wavelength` picks one band; the public scenes without it render
/// only in *_spectral_polarized variants, and those with it use the stokes integrator. Refused,
/// saying which of the two applies and naming the data file.
[[noreturn]] void refuse_measured_polarized(MitsubaPlugin& plugin) {
  std::optional<std::string> file = plugin.take_string("filename");
  const std::string data = file ? "its data file \"" + *file + "\"" : "its data file";
  if (!plugin.has("wavelength")) {
    fail_at(plugin.element(),
            "measured_polarized is not supported: without a `wavelength` Mitsuba renders it only "
            "in *_spectral_polarized variants (its RGB variants refuse it), while Tessera renders "
            "RGB without polarization; nor does Tessera read " + data +
                " (a .pbsdf polarimetric BRDF tensor)");
  }
  fail_at(plugin.element(),
          "measured_polarized is not supported: Tessera does not read " + data +
              " (a .pbsdf polarimetric BRDF tensor measured in five wavelength bands)");
}

/// A BSDF's name: its id, else its type and where it is ("diffuse (scene.xml line 12)"). The
/// material takes it, and a cycle's message names its BSDFs by it.
std::string bsdf_name(const MitsubaElement& bsdf) {
  const std::string* id = bsdf.attribute("id");
  if (id && !id->empty()) return *id;
  const std::string* type = bsdf.attribute("type");
  return (type ? *type : std::string("bsdf")) + " (" + bsdf.file + " line " +
         std::to_string(bsdf.line) + ")";
}

}  // namespace

Material MitsubaMaterials::read(const MitsubaElement& bsdf) {
  if (bsdf.tag != "bsdf") fail_at(bsdf, "is no <bsdf>");
  auto repeat = std::find(reading_.begin(), reading_.end(), &bsdf);
  if (repeat != reading_.end()) {
    std::string cycle;
    for (auto it = repeat; it != reading_.end(); ++it) {
      cycle += "\"" + printable(bsdf_name(**it)) + "\" -> ";
    }
    fail_at(bsdf, "contains itself through <ref> (" + cycle + "\"" + printable(bsdf_name(bsdf)) +
                      "\")");
  }
  if (reading_.size() >= size_t(kMaxMitsubaElementDepth)) {
    fail_at(bsdf, "BSDFs nested more than " + std::to_string(kMaxMitsubaElementDepth) +
                      " deep (through <ref>s)");
  }
  reading_.push_back(&bsdf);
  Material m = read_plugin(bsdf);
  reading_.pop_back();
  return m;
}

Material MitsubaMaterials::read_plugin(const MitsubaElement& bsdf) {
  MitsubaPlugin plugin(bsdf, ids_);
  const std::string& type = plugin.type();
  Material m;
  if (type == "diffuse") {
    m = read_diffuse(plugin, textures_);
  } else if (type == "conductor" || type == "roughconductor") {
    m = read_conductor(plugin, textures_, type == "roughconductor");
  } else if (type == "dielectric") {
    m = read_dielectric(plugin, textures_, MaterialType::glass);
  } else if (type == "roughdielectric") {
    m = read_dielectric(plugin, textures_, MaterialType::rough_glass);
  } else if (type == "thindielectric") {
    m = read_dielectric(plugin, textures_, MaterialType::thin_glass);
  } else if (type == "plastic" || type == "roughplastic") {
    m = read_plastic(plugin, textures_, type == "roughplastic");
  } else if (type == "principled") {
    m = read_principled(plugin, textures_);
  } else if (type == "principledthin") {
    m = read_principled_thin(plugin, textures_);
  } else if (type == "pplastic") {
    m = read_pplastic(plugin, textures_);
  } else if (type == "polarizer") {
    m = read_polarizer(plugin, textures_);
  } else if (type == "hair") {
    m = read_hair(plugin, textures_, read_relative_ior(plugin, "amber"));
  } else if (type == "blendbsdf") {
    m = read_blend(plugin);
  } else if (type == "null") {
    m = read_null();
  } else if (type == "twosided") {
    m = read_twosided(plugin);
  } else if (type == "mask" || type == "bumpmap" || type == "normalmap") {
    m = read_wrapper(plugin);
  } else if (type == "measured_polarized") {
    refuse_measured_polarized(plugin);
  } else {
    fail_at(bsdf, std::string("unsupported BSDF (") + kSupported + ")");
  }
  plugin.finish();
  return m;
}

uint32_t MitsubaMaterials::add_named(Material material, const std::string& name) {
  std::string unique = name;
  for (int k = 2; names_.count(unique); ++k) unique = name + " #" + std::to_string(k);
  names_.insert(unique);
  material.name = unique;
  materials_.push_back(std::move(material));
  return uint32_t(materials_.size() - 1);
}

uint32_t MitsubaMaterials::add(Material material, const MitsubaElement& bsdf) {
  return add_named(std::move(material), bsdf_name(bsdf));
}

uint32_t MitsubaMaterials::of(const MitsubaElement& bsdf) {
  auto it = index_of_.find(&bsdf);
  if (it != index_of_.end()) return it->second;
  Material material = read(bsdf);
  uint32_t index = add(std::move(material), bsdf);
  index_of_[&bsdf] = index;
  return index;
}

uint32_t MitsubaMaterials::default_material(bool emitter) {
  std::optional<uint32_t>& index = emitter ? default_emitter_ : default_;
  if (!index) {
    Material diffuse;
    diffuse.type = MaterialType::diffuse;
    diffuse.reflectance.value = glm::dvec3(emitter ? 0.0 : 0.5);
    index = add_named(std::move(diffuse), emitter ? "(Mitsuba default for a light: black diffuse)"
                                                  : "(Mitsuba default diffuse)");
  }
  return *index;
}

std::vector<Material> MitsubaMaterials::take() {
  std::vector<Material> result = std::move(materials_);
  materials_.clear();
  index_of_.clear();
  names_.clear();
  default_.reset();
  default_emitter_.reset();
  return result;
}

}  // namespace tessera
