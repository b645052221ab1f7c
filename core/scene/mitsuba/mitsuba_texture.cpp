#include "scene/mitsuba/mitsuba_texture.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/message_text.h"
#include "scene/scene_error.h"
#include "scene/volume_texture_check.h"

namespace tessera {
namespace {

/// A checkerboard colour: every channel >= 0, not bounded above (it may give an eta or a
/// radiance). A <spectrum> is read as a reflectance, as before.
glm::dvec3 checker_color(MitsubaPlugin& plugin, std::string_view name, glm::dvec3 fallback) {
  std::optional<glm::dvec3> color = plugin.take_color(name);
  if (!color) return fallback;
  for (int i = 0; i < 3; ++i) {
    if (!((*color)[i] >= 0)) {
      fail_at(*plugin.property(name), std::string(name) + " must be >= 0 in every channel (got " +
                                          format_number((*color)[i]) + ")");
    }
  }
  return *color;
}

std::string lower_extension(const std::string& path) {
  size_t dot = path.rfind('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

TextureFilter read_filter(MitsubaPlugin& plugin) {
  std::optional<std::string> filter = plugin.take_string("filter_type");
  if (!filter || *filter == "bilinear") return TextureFilter::bilinear;
  if (*filter == "nearest") return TextureFilter::nearest;
  fail_at(*plugin.property("filter_type"),
          "\"" + printable(*filter) + "\" is no filter_type (bilinear or nearest)");
}

TextureWrap read_wrap(MitsubaPlugin& plugin) {
  std::optional<std::string> wrap = plugin.take_string("wrap_mode");
  if (!wrap || *wrap == "repeat") return TextureWrap::repeat;
  if (*wrap == "mirror") return TextureWrap::mirror;
  if (*wrap == "clamp") return TextureWrap::clamp;
  fail_at(*plugin.property("wrap_mode"),
          "\"" + printable(*wrap) + "\" is no wrap_mode (repeat, mirror or clamp)");
}

void check_range(const MitsubaElement* where, const glm::dvec3& value, MitsubaColorRole role) {
  for (int c = 0; c < 3; ++c) {
    bool ok = role == MitsubaColorRole::reflectance ? value[c] >= 0 && value[c] <= 1
                                                    : value[c] >= 0;
    if (!ok && where) {
      fail_at(*where, std::string("each channel must be ") +
                          (role == MitsubaColorRole::reflectance ? "in [0, 1]" : ">= 0") +
                          " (got " + format_number(value[c]) + ")");
    }
  }
}

/// rawconstant's `value`: a <float> (one channel) or a <vector> (three), used as written.
void read_raw_value(MitsubaPlugin& plugin, Texture& texture) {
  const MitsubaElement* value = plugin.property("value");
  if (!value) {
    fail_at(plugin.element(), "missing \"value\" (a <float> or a <vector>)");
  }
  if (value->tag == "float" || value->tag == "integer") {
    texture.value = glm::dvec3(*plugin.take_float("value"));
    texture.channels = 1;
  } else if (value->tag == "vector" || value->tag == "point") {
    texture.value = *plugin.take_point("value");
    texture.channels = 3;
  } else {
    fail_at(*value, "rawconstant's value is a <float> or a <vector>");
  }
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(texture.value[c])) fail_at(*value, "must be finite");
  }
}

/// constvolume's value: a <float> (one channel), an <rgb> or <spectrum> (three channels), any
/// finite numbers (Mitsuba 3.9.1 range-checks neither), or 1 (one channel) when absent.
void read_constant_volume(MitsubaPlugin& plugin, Texture& texture) {
  texture.value = glm::dvec3(1.0);
  texture.channels = 1;
  const MitsubaElement* written = plugin.property("value");
  if (!written) return;
  if (written->tag == "float" || written->tag == "integer") {
    texture.value = glm::dvec3(*plugin.take_float("value"));
  } else if (written->tag == "rgb" || written->tag == "spectrum") {
    texture.value = *plugin.take_color("value", MitsubaColorRole::reflectance);
    texture.channels = 3;
  } else {
    fail_at(*written, "constvolume's value is a <float>, an <rgb> or a <spectrum>");
  }
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(texture.value[c])) fail_at(*written, "must be finite");
  }
}

/// The nested <volume> of a volume texture: gridvolume or constvolume.
void read_volume_plugin(const MitsubaElement& element, const MitsubaIds& ids,
                        MitsubaFileResolver& files, std::vector<std::string>& referenced_files,
                        Texture& texture) {
  if (element.tag != "volume") {
    fail_at(element, "a volume texture's \"volume\" is a <volume> (gridvolume or "
                     "constvolume), a <float> or an <rgb>");
  }
  MitsubaPlugin plugin(element, ids);
  if (plugin.type() == "constvolume") {
    read_constant_volume(plugin, texture);
    // A constant is the same everywhere a surface looks it up; its to_world still places the
    // box outside which a heterogeneous medium is empty (Mitsuba's Volume::bbox).
    if (std::optional<Transform> to_world = plugin.take_transform("to_world")) {
      texture.volume_to_world = to_world->matrix();
    }
    plugin.finish();
    return;
  }
  if (plugin.type() != "gridvolume") {
    fail_at(element, "unsupported volume (Tessera's volume texture reads gridvolume and "
                     "constvolume)");
  }
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(element, "missing <string name=\"filename\"> (the .vol grid file)");
  const MitsubaElement& where = *plugin.property("filename");
  texture.file = files.resolve(where, *filename);
  if (std::find(referenced_files.begin(), referenced_files.end(), texture.file) ==
      referenced_files.end()) {
    referenced_files.push_back(texture.file);
  }
  try {
    texture.grid = read_volume_texture_grid(files.read(texture.file), texture.file);
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
  std::optional<std::string> filter = plugin.take_string("filter_type");
  texture.filter = TextureFilter::bilinear;
  if (filter && *filter == "nearest") {
    texture.filter = TextureFilter::nearest;
  } else if (filter && *filter != "trilinear") {
    fail_at(*plugin.property("filter_type"), "Invalid filter type \"" + printable(*filter) +
                                                 "\", must be one of: \"nearest\" or "
                                                 "\"trilinear\" (Mitsuba's message)");
  }
  std::optional<std::string> wrap = plugin.take_string("wrap_mode");
  texture.wrap = TextureWrap::clamp;
  if (wrap && *wrap == "repeat") {
    texture.wrap = TextureWrap::repeat;
  } else if (wrap && *wrap == "mirror") {
    texture.wrap = TextureWrap::mirror;
  } else if (wrap && *wrap != "clamp") {
    fail_at(*plugin.property("wrap_mode"), "Invalid wrap mode \"" + printable(*wrap) +
                                               "\", must be one of: \"repeat\", \"mirror\", "
                                               "or \"clamp\" (Mitsuba's message)");
  }
  if (std::optional<Transform> to_world = plugin.take_transform("to_world")) {
    texture.volume_to_world = to_world->matrix();
  }
  if (plugin.take_boolean("use_grid_bbox").value_or(false)) {
    // Mitsuba maps the file's bounding box onto [0, 1]^3 before to_world.
    const glm::dvec3 lo(texture.grid->bbox_min), extent(glm::dvec3(texture.grid->bbox_max) - lo);
    if (!(extent.x > 0 && extent.y > 0 && extent.z > 0)) {
      fail_at(*plugin.property("use_grid_bbox"),
              "the grid file's bounding box is empty, so it cannot place the grid");
    }
    texture.volume_to_world =
        glm::scale(glm::translate(texture.volume_to_world, lo), extent);
  }
  plugin.ignore("raw");        // RGB rendering: no spectral upsampling to switch off
  plugin.ignore("accel");      // GPU texture units: the same lookups
  plugin.ignore("max_value");  // a medium's majorant; no lookup changes
  plugin.finish();
}

}  // namespace

glm::dmat3 read_mitsuba_to_uv(MitsubaPlugin& plugin) {
  std::optional<Transform> to_uv = plugin.take_transform("to_uv");
  if (!to_uv) return glm::dmat3(1.0);
  const glm::dmat4& m = to_uv->matrix();
  glm::dmat3 uv(1.0);
  for (int row = 0; row < 2; ++row) {
    uv[0][row] = m[0][row];
    uv[1][row] = m[1][row];
    uv[2][row] = m[3][row];
  }
  return uv;
}

Texture MitsubaTextures::read(const MitsubaElement& element) {
  MitsubaPlugin plugin(element, ids_);
  Texture texture;
  texture.origin = element.where();
  if (plugin.type() == "bitmap") {
    texture.kind = TextureKind::bitmap;
    std::optional<std::string> filename = plugin.take_string("filename");
    if (!filename) fail_at(element, "missing <string name=\"filename\">");
    texture.file = files_.resolve(*plugin.property("filename"), *filename);
    if (std::find(referenced_files_.begin(), referenced_files_.end(), texture.file) ==
        referenced_files_.end()) {
      referenced_files_.push_back(texture.file);
    }
    bool raw = plugin.take_boolean("raw").value_or(false);
    std::string ext = lower_extension(texture.file);
    bool linear_file = ext == "exr" || ext == "hdr" || ext == "pfm";
    texture.color_space =
        raw || linear_file ? TextureColorSpace::linear : TextureColorSpace::srgb;
    texture.filter = read_filter(plugin);
    texture.wrap = read_wrap(plugin);
    plugin.ignore("accel");   // Mitsuba's GPU texture units: the same lookups
    plugin.ignore("format");  // storage precision of the texels in Mitsuba's memory
  } else if (plugin.type() == "checkerboard") {
    texture.kind = TextureKind::checkerboard;
    texture.color0 = checker_color(plugin, "color0", glm::dvec3(0.4));
    texture.color1 = checker_color(plugin, "color1", glm::dvec3(0.2));
  } else if (plugin.type() == "rawconstant") {
    texture.kind = TextureKind::rawconstant;
    read_raw_value(plugin, texture);
    plugin.finish();  // no to_uv: the value is the same everywhere
    return texture;
  } else if (plugin.type() == "mesh_attribute") {
    texture.kind = TextureKind::mesh_attribute;
    std::optional<std::string> name = plugin.take_string("name");
    if (!name) fail_at(element, "missing <string name=\"name\"> (the mesh attribute to read)");
    if (!MeshAttribute::is_vertex_attribute_name(*name) &&
        !MeshAttribute::is_face_attribute_name(*name)) {
      fail_at(*plugin.property("name"), "the attribute's name must start with \"vertex_\" or "
                                        "\"face_\" (got \"" + *name + "\")");
    }
    texture.attribute = *name;
    texture.scale = plugin.take_float("scale").value_or(1.0);
    plugin.finish();  // no to_uv: the shape's attribute is looked up where it is hit
    return texture;
  } else if (plugin.type() == "volume") {
    // Mitsuba's `volume` texture: its nested <volume> (src/textures/volume.cpp).
    texture.kind = TextureKind::volume;
    std::optional<MitsubaObject> volume = plugin.take_named_object("volume");
    if (!volume) {
      if (const MitsubaElement* written = plugin.property("volume")) {
        fail_at(*written, "The property \"volume\" has the wrong type (expected object, got " +
                              written->tag + ") (Mitsuba's message; a constant is "
                              "<volume type=\"constvolume\" name=\"volume\">)");
      }
      fail_at(element, "missing <volume name=\"volume\"> (gridvolume or constvolume; Mitsuba "
                       "3.9.1 loads a volume texture without one and crashes at its first "
                       "lookup)");
    }
    read_volume_plugin(*volume->element, ids_, files_, referenced_files_, texture);
    plugin.finish();  // no to_uv: the point's position is looked up
    return texture;
  } else {
    fail_at(element,
            "unsupported texture (Tessera has bitmap, checkerboard, rawconstant, "
            "mesh_attribute and volume; bake others into a bitmap)");
  }
  texture.to_uv = read_mitsuba_to_uv(plugin);
  plugin.finish();
  return texture;
}

int32_t MitsubaTextures::of(const MitsubaElement& element) {
  auto it = index_of_.find(&element);
  if (it != index_of_.end()) return it->second;
  if (element.tag != "texture") {
    fail_at(element, "is no <texture> (a colour parameter takes <rgb>, <float>, <spectrum> or "
                     "a <texture>)");
  }
  return add(element, read(element));
}

int32_t MitsubaTextures::of_volume(const MitsubaElement& element) {
  auto it = index_of_.find(&element);
  if (it != index_of_.end()) return it->second;
  Texture texture;
  texture.origin = element.where();
  texture.kind = TextureKind::volume;
  read_volume_plugin(element, ids_, files_, referenced_files_, texture);
  return add(element, std::move(texture));
}

int32_t MitsubaTextures::add(const MitsubaElement& element, Texture texture) {
  const std::string* id = element.attribute("id");
  std::string name = id && !id->empty() ? *id
                                        : *element.attribute("type") + " (" + element.file +
                                              " line " + std::to_string(element.line) + ")";
  std::string unique = name;
  for (int k = 2; names_.count(unique); ++k) unique = name + " #" + std::to_string(k);
  names_.insert(unique);
  texture.name = unique;
  textures_.push_back(std::move(texture));
  int32_t index = int32_t(textures_.size() - 1);
  index_of_[&element] = index;
  return index;
}

std::vector<Texture> MitsubaTextures::take() {
  std::vector<Texture> result = std::move(textures_);
  textures_.clear();
  index_of_.clear();
  names_.clear();
  return result;
}

TexturedColor read_textured_color(MitsubaPlugin& plugin, std::string_view name,
                                  const glm::dvec3& fallback, MitsubaColorRole role,
                                  MitsubaTextures& textures) {
  TexturedColor color;
  if (std::optional<MitsubaObject> texture = plugin.take_named_object(name)) {
    color.value = glm::dvec3(1);
    color.texture = textures.of(*texture->element);
    const std::string& type = plugin.type();
    if (textures.at(color.texture).kind == TextureKind::volume &&
        (type == "plastic" || type == "roughplastic" || type == "pplastic")) {
      // Mitsuba 3.9.1 throws "Texture::mean(): not implemented!" when it loads such a plastic.
      fail_at(*texture->written, "Mitsuba's " + type + " takes the mean of its reflectances "
                                 "when it loads, which a volume texture does not have "
                                 "(Mitsuba: \"Texture::mean(): not implemented!\")");
    }
    return color;
  }
  std::optional<glm::dvec3> value = plugin.take_color(name, role);
  color.value = value.value_or(fallback);
  if (value) check_range(plugin.property(name), color.value, role);
  return color;
}

TexturedFloat read_textured_float(MitsubaPlugin& plugin, std::string_view name, double fallback,
                                  MitsubaTextures& textures) {
  TexturedFloat result;
  if (std::optional<MitsubaObject> texture = plugin.take_named_object(name)) {
    result.value = 1;
    result.texture = textures.of(*texture->element);
    const Texture& t = textures.at(result.texture);
    if (t.kind == TextureKind::rawconstant && t.channels != 1) {
      fail_at(*texture->written,
              "a rawconstant <vector> has no scalar value (Mitsuba's eval_1 refuses it): give "
              "\"" + std::string(name) + "\" a <float> value");
    }
    return result;
  }
  const MitsubaElement* written = plugin.property(name);
  if (written && written->tag == "rgb") {
    // An <rgb> makes Mitsuba's sRGB reflectance texture (each channel in [0, 1]), whose scalar
    // value, eval_1, is the mean of its channels in the RGB variants (src/spectra/srgb.cpp);
    // Bitterli's scenes in Mitsuba 3 form give a mask's opacity so.
    const glm::dvec3 rgb = *plugin.take_color(name);
    for (int c = 0; c < 3; ++c) {
      if (!(rgb[c] >= 0 && rgb[c] <= 1)) {
        fail_at(*written, "each channel must be in [0, 1] (got " + format_number(rgb[c]) +
                              "), as Mitsuba's sRGB reflectance demands");
      }
    }
    result.value = (rgb.x + rgb.y + rgb.z) / 3;
    return result;
  }
  result.value = plugin.take_float(name).value_or(fallback);
  return result;
}

}  // namespace tessera
