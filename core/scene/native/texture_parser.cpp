#include "scene/native/texture_parser.h"

#include <cmath>
#include <algorithm>
#include <cctype>

#include "scene/native/transform_parser.h"
#include "scene/scene_error.h"
#include "scene/file_reader.h"
#include "scene/bundle_path.h"
#include "scene/volume_texture_check.h"

namespace tessera {
namespace {

template <typename Enum, size_t N>
Enum parse_enum(const JsonValue& value, const std::pair<const char*, Enum> (&names)[N]) {
  const std::string& text = value.string();
  std::string expected;
  for (size_t i = 0; i < N; ++i) {
    if (text == names[i].first) return names[i].second;
    expected += std::string(i ? (i + 1 == N ? " or " : ", ") : "") + "\"" + names[i].first + "\"";
  }
  value.fail("must be " + expected + " (got \"" + printable(text) + "\")");
}

constexpr std::pair<const char*, TextureColorSpace> kColorSpaces[] = {
    {"srgb", TextureColorSpace::srgb}, {"linear", TextureColorSpace::linear}};
constexpr std::pair<const char*, TextureFilter> kFilters[] = {
    {"bilinear", TextureFilter::bilinear}, {"nearest", TextureFilter::nearest}};
constexpr std::pair<const char*, TextureFilter> kVolumeFilters[] = {
    {"trilinear", TextureFilter::bilinear}, {"nearest", TextureFilter::nearest}};
constexpr std::pair<const char*, TextureWrap> kWraps[] = {{"repeat", TextureWrap::repeat},
                                                          {"mirror", TextureWrap::mirror},
                                                          {"clamp", TextureWrap::clamp}};

/// Float images are linear, others sRGB: Mitsuba's default for bitmaps.
TextureColorSpace default_color_space(const std::string& file) {
  std::string lower = file;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* ext : {".exr", ".hdr", ".pfm"}) {
    if (lower.ends_with(ext)) return TextureColorSpace::linear;
  }
  return TextureColorSpace::srgb;
}

/// "to_uv": [[a, b, c], [d, e, f]]: u' = a u + b v + c, v' = d u + e v + f.
glm::dmat3 parse_to_uv(const JsonValue& value) {
  std::vector<JsonValue> rows = value.elements(2);
  glm::dmat3 m(1.0);
  for (int r = 0; r < 2; ++r) {
    std::vector<JsonValue> row = rows[r].elements(3);
    for (int c = 0; c < 3; ++c) m[c][r] = row[c].number();
  }
  if (m[0][0] * m[1][1] - m[1][0] * m[0][1] == 0) value.fail("must be invertible");
  return m;
}

glm::dvec3 ranged_rgb(const JsonValue& value, ColorRange range) {
  glm::dvec3 rgb = value.vec3();
  std::vector<JsonValue> channels = value.elements(3);
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < range.min || rgb[i] > range.max) {
      std::string bound = range.max < 1e300 ? "in [" + format_number(range.min) + ", " +
                                                  format_number(range.max) + "]"
                                            : ">= " + format_number(range.min);
      channels[i].fail("must be " + bound + " (got " + format_number(rgb[i]) + ")");
    }
  }
  return rgb;
}

void add_referenced(const std::string& file, std::vector<std::string>& referenced_files) {
  if (std::find(referenced_files.begin(), referenced_files.end(), file) ==
      referenced_files.end()) {
    referenced_files.push_back(file);
  }
}

/// {"type": "volume", "file", "transform", "filter", "wrap"} or {"type": "volume", "value",
/// "transform"}.
void parse_volume(const JsonValue& value, Texture& texture,
                  std::vector<std::string>& referenced_files, const FileReader& reader) {
  texture.kind = TextureKind::volume;
  texture.wrap = TextureWrap::clamp;  // Mitsuba's default for volumes
  if (auto constant = value.find("value")) {
    value.expect_object({"type", "value", "transform"}, "a constant volume");
    if (constant->json().is_number()) {
      texture.value = glm::dvec3(constant->number());
      texture.channels = 1;
    } else {
      texture.value = constant->vec3();
      texture.channels = 3;
    }
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(texture.value[c])) constant->fail("must be finite");
    }
    // Places the box outside which a heterogeneous medium reading it is empty (docs/scenes.md).
    if (auto t = value.find("transform")) texture.volume_to_world = parse_transform(*t).matrix();
    return;
  }
  value.expect_object({"type", "file", "transform", "filter", "wrap"}, "a volume");
  JsonValue file = value.at("file");
  texture.file = check_bundle_path(file.string(), file.path());
  add_referenced(texture.file, referenced_files);
  try {
    texture.grid = read_volume_texture_grid(reader(texture.file), texture.file);
  } catch (const SceneError& e) {
    file.fail(e.what());
  }
  if (auto t = value.find("transform")) texture.volume_to_world = parse_transform(*t).matrix();
  if (auto f = value.find("filter")) texture.filter = parse_enum(*f, kVolumeFilters);
  if (auto w = value.find("wrap")) texture.wrap = parse_enum(*w, kWraps);
}

Texture parse_texture(const std::string& name, const JsonValue& value,
                      std::vector<std::string>& referenced_files, const FileReader& reader) {
  if (!value.json().is_object()) value.expect_object({}, "a texture");
  Texture texture;
  texture.name = name;
  texture.origin = value.path();
  std::string type = value.at("type").string();
  if (type == "bitmap") {
    value.expect_object({"type", "file", "color_space", "filter", "wrap", "to_uv"}, "a bitmap");
    JsonValue file = value.at("file");
    texture.file = check_bundle_path(file.string(), file.path());
    add_referenced(texture.file, referenced_files);
    texture.color_space = default_color_space(texture.file);
    if (auto c = value.find("color_space")) texture.color_space = parse_enum(*c, kColorSpaces);
    if (auto f = value.find("filter")) texture.filter = parse_enum(*f, kFilters);
    if (auto w = value.find("wrap")) texture.wrap = parse_enum(*w, kWraps);
  } else if (type == "checkerboard") {
    texture.kind = TextureKind::checkerboard;
    value.expect_object({"type", "color0", "color1", "to_uv"}, "a checkerboard");
    // Unbounded above, as a bitmap's texels are: a checkerboard may feed an index of
    // refraction, an emitter's radiance or a reflectance above 1 (Mitsuba clamps none).
    if (auto c = value.find("color0")) texture.color0 = ranged_rgb(*c, {0, 1e300});
    if (auto c = value.find("color1")) texture.color1 = ranged_rgb(*c, {0, 1e300});
  } else if (type == "rawconstant") {
    texture.kind = TextureKind::rawconstant;
    value.expect_object({"type", "value"}, "a rawconstant");
    JsonValue raw = value.at("value");
    if (raw.json().is_number()) {
      texture.value = glm::dvec3(raw.number());
      texture.channels = 1;
    } else {
      texture.value = raw.vec3();
      texture.channels = 3;
    }
    return texture;
  } else if (type == "mesh_attribute") {
    texture.kind = TextureKind::mesh_attribute;
    value.expect_object({"type", "attribute", "scale"}, "a mesh_attribute");
    JsonValue attribute = value.at("attribute");
    texture.attribute = attribute.string();
    if (!MeshAttribute::is_vertex_attribute_name(texture.attribute) &&
        !MeshAttribute::is_face_attribute_name(texture.attribute)) {
      attribute.fail("must start with \"vertex_\" or \"face_\" (got \"" +
                     printable(texture.attribute) + "\")");
    }
    if (auto scale = value.find("scale")) {
      texture.scale = scale->number();
      if (!std::isfinite(texture.scale)) scale->fail("must be a finite number");
    }
    return texture;
  } else if (type == "volume") {
    parse_volume(value, texture, referenced_files, reader);
    return texture;
  } else {
    value.at("type").fail("unknown texture type \"" + printable(type) +
                          "\" (expected bitmap, checkerboard, rawconstant, mesh_attribute or "
                          "volume)");
  }
  if (auto t = value.find("to_uv")) texture.to_uv = parse_to_uv(*t);
  return texture;
}

}  // namespace

TextureNames parse_textures(const JsonValue& value, std::vector<Texture>& textures,
                            std::vector<std::string>& referenced_files, const FileReader& reader) {
  TextureNames names;
  for (const auto& [name, texture] : value.members()) {
    if (name.empty()) texture.fail("a texture name must not be empty");
    names[name] = int32_t(textures.size());
    textures.push_back(parse_texture(name, texture, referenced_files, reader));
  }
  return names;
}

int32_t texture_index(const JsonValue& value, const TextureNames& textures) {
  const std::string& name = value.string();
  auto it = textures.find(name);
  if (it == textures.end()) value.fail("unknown texture \"" + printable(name) + "\"");
  return it->second;
}

TexturedColor parse_textured_color(const JsonValue& value, const TextureNames& textures,
                                   ColorRange range) {
  if (!value.json().is_object()) return {ranged_rgb(value, range), -1};
  value.expect_object({"texture", "scale"}, "a textured colour");
  TexturedColor color{{1, 1, 1}, texture_index(value.at("texture"), textures)};
  if (auto scale = value.find("scale")) {
    if (scale->json().is_number()) {
      double s = scale->number();
      if (s < 0) scale->fail("must be >= 0 (got " + format_number(s) + ")");
      color.value = glm::dvec3(s);
    } else {
      color.value = ranged_rgb(*scale, {});
    }
  }
  return color;
}

TexturedFloat parse_textured_float(const JsonValue& value, const TextureNames& textures,
                                   double min, double max, bool min_open) {
  if (!value.json().is_object()) {
    double x = value.number();
    if ((min_open ? !(x > min) : !(x >= min)) || x > max) {
      std::string bound = max < 1e300 ? std::string("in ") + (min_open ? "(" : "[") +
                                            format_number(min) + ", " + format_number(max) + "]"
                                      : std::string(min_open ? "> " : ">= ") + format_number(min);
      value.fail("must be " + bound + " (got " + format_number(x) + ")");
    }
    return {x, -1};
  }
  value.expect_object({"texture", "scale"}, "a textured number");
  TexturedFloat result{1, texture_index(value.at("texture"), textures)};
  if (auto scale = value.find("scale")) {
    result.value = scale->number();
    if (result.value < 0) scale->fail("must be >= 0 (got " + format_number(result.value) + ")");
  }
  return result;
}

}  // namespace tessera
