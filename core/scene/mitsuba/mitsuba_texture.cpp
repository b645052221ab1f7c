#include "scene/mitsuba/mitsuba_texture.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "scene/native/json_value.h"

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
  } else {
    fail_at(element,
            "unsupported texture (Tessera has bitmap, checkerboard, rawconstant and "
            "mesh_attribute; bake others into a bitmap)");
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
  Texture texture = read(element);
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
