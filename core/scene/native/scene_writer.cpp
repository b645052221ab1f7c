#include "scene/native/scene_writer.h"

#include <charconv>
#include <cmath>
#include <set>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not one.
size_t utf8_sequence(std::string_view text, size_t i) {
  auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  unsigned char c = byte(i);
  size_t length = c < 0x80           ? 1
                  : (c >> 5) == 0x6  ? 2
                  : (c >> 4) == 0xe  ? 3
                  : (c >> 3) == 0x1e ? 4
                                     : 0;
  if (length == 0 || i + length > text.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) >> 6) != 0x2) return 0;
  }
  if (length == 2 && c < 0xc2) return 0;                          // overlong
  if (length == 3 && c == 0xe0 && byte(i + 1) < 0xa0) return 0;   // overlong
  if (length == 3 && c == 0xed && byte(i + 1) >= 0xa0) return 0;  // surrogates
  if (length == 4 && c == 0xf0 && byte(i + 1) < 0x90) return 0;   // overlong
  if (length == 4 && (c > 0xf4 || (c == 0xf4 && byte(i + 1) >= 0x90))) return 0;
  return length;
}

/// `text` with bytes that are not UTF-8 replaced by '?': JSON text is UTF-8.
std::string valid_utf8(std::string_view text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    size_t length = utf8_sequence(text, i);
    if (length == 0) {
      out += '?';
      ++i;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
  }
  return out;
}

/// A JSON string literal of valid UTF-8 `text`.
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20 || byte == 0x7f) {
      static const char kHex[] = "0123456789abcdef";
      out += "\\u00";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// The shortest decimal that reads back as `x` (std::to_chars); -0 as "-0.0", which the JSON
/// reader takes as a double, keeping its sign (a bare "-0" reads as the integer 0).
std::string number(double x, const std::string& what) {
  if (!std::isfinite(x)) {
    throw SceneError(what + ": " + format_number(x) + " cannot be written in JSON");
  }
  if (x == 0) return std::signbit(x) ? "-0.0" : "0";
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string vec3(const glm::dvec3& v, const std::string& what) {
  return "[" + number(v.x, what) + ", " + number(v.y, what) + ", " + number(v.z, what) + "]";
}

const char* fov_axis_name(FovAxis axis) {
  switch (axis) {
    case FovAxis::x:
      return "x";
    case FovAxis::y:
      return "y";
    case FovAxis::smaller:
      return "smaller";
    case FovAxis::larger:
      return "larger";
  }
  return "x";
}

std::string camera_json(const Camera& c) {
  return "  \"camera\": {\n    \"position\": " + vec3(c.position, "camera.position") +
         ",\n    \"look_at\": " + vec3(c.look_at, "camera.look_at") +
         ",\n    \"up\": " + vec3(c.up, "camera.up") +
         ",\n    \"fov\": " + number(c.fov_deg, "camera.fov") + ", \"fov_axis\": \"" +
         fov_axis_name(c.fov_axis) +
         "\",\n    \"aperture_radius\": " + number(c.aperture_radius, "camera.aperture_radius") +
         ", \"focus_distance\": " + number(c.focus_distance, "camera.focus_distance") + "\n  },\n";
}

/// Material names as written: valid UTF-8, non-empty and unique.
std::vector<std::string> material_names(const std::vector<Material>& materials) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const Material& m : materials) {
    std::string base = valid_utf8(m.name);
    if (base.empty()) base = "material";
    std::string name = base;
    for (int k = 2; used.count(name); ++k) name = base + " #" + std::to_string(k);
    used.insert(name);
    names.push_back(name);
  }
  return names;
}

std::string material_json(const Material& m, const std::string& name) {
  std::string what = "materials." + printable(name);
  std::string body;
  switch (m.type) {
    case MaterialType::diffuse:
      body = "\"type\": \"diffuse\", \"reflectance\": " + vec3(m.reflectance.value, what) +
             ", \"two_sided\": " + (m.two_sided ? "true" : "false");
      break;
    case MaterialType::mirror:
      body =
          std::string("\"type\": \"mirror\", \"two_sided\": ") + (m.two_sided ? "true" : "false");
      break;
    case MaterialType::glass:
      body = "\"type\": \"glass\", \"ior\": " + number(m.ior, what + ".ior");
      break;
    // Native JSON has no keys for these yet (docs/scenes.md): refused by name rather than
    // written as an empty material that would read back as a diffuse one.
    case MaterialType::conductor:
    case MaterialType::rough_conductor:
    case MaterialType::rough_glass:
    case MaterialType::thin_glass:
    case MaterialType::plastic:
    case MaterialType::rough_plastic:
      throw SceneError(what + ": this material type cannot be written as native JSON yet (it has"
                              " diffuse, mirror and glass)");
  }
  return "    " + json_string(name) + ": {" + body + "}";
}

void append_points(std::string& out, const char* key, const std::vector<glm::dvec3>& points,
                   const std::string& what) {
  out += ",\n      \"";
  out += key;
  out += "\": [";
  for (size_t i = 0; i < points.size(); ++i) {
    out += i ? ",\n        " : "\n        ";
    out += vec3(points[i], what);
  }
  out += "\n      ]";
}

std::string shape_json(const Shape& s, size_t index, const std::vector<Material>& materials,
                       const std::vector<std::string>& names) {
  std::string what = "shapes[" + std::to_string(index) + "] (" + printable(s.origin) + ")";
  if (s.material >= materials.size()) throw SceneError(what + ": material index out of range");
  std::string out = "    {";
  if (s.kind == Shape::Kind::sphere) {
    out += "\"type\": \"sphere\", \"center\": " + vec3(s.center, what) +
           ", \"radius\": " + number(s.radius, what) +
           ", \"flip_normals\": " + (s.flip_normals ? "true" : "false");
  } else {
    out += "\"type\": \"triangles\"";
  }
  out += ", \"material\": " + json_string(names[s.material]);
  if (s.is_emitter()) out += ",\n      \"emission\": " + vec3(s.emission, what);
  if (s.is_emitter() && s.two_sided_emission) {
    const Material& m = materials[s.material];
    if (!m.two_sided && m.type != MaterialType::glass) {
      throw SceneError(what +
                       ": it emits from both sides but its material is one-sided, which "
                       "the native format cannot say");
    }
    out += ", \"two_sided\": true";
  }
  if (s.kind == Shape::Kind::triangles) {
    if (s.indices.empty()) throw SceneError(what + ": no triangles");
    if (!s.normals.empty() && s.normals.size() != s.positions.size()) {
      throw SceneError(what + ": one normal per vertex is needed");
    }
    append_points(out, "vertices", s.positions, what);
    out += ",\n      \"indices\": [";
    for (size_t i = 0; i < s.indices.size(); ++i) {
      const glm::u32vec3& t = s.indices[i];
      out += i ? ",\n        [" : "\n        [";
      out += std::to_string(t.x) + ", " + std::to_string(t.y) + ", " + std::to_string(t.z) + "]";
    }
    out += "\n      ]";
    if (!s.normals.empty()) append_points(out, "normals", s.normals, what);
  }
  return out + "}";
}

}  // namespace

std::string write_scene_json(const Scene& scene, const std::string& comment) {
  std::string out;
  if (!comment.empty()) out += "// " + valid_utf8(printable(comment)) + "\n";
  out += "{\n  \"tessera\": 1,\n";
  out += camera_json(scene.camera);
  out += "  \"film\": {\"width\": " + std::to_string(scene.film.width) +
         ", \"height\": " + std::to_string(scene.film.height) + "},\n";
  out += "  \"render\": {\"spp\": " + std::to_string(scene.render.spp) +
         ", \"max_depth\": " + std::to_string(scene.render.max_depth) +
         ", \"seed\": " + std::to_string(scene.render.seed) + "},\n";
  std::vector<std::string> names = material_names(scene.materials);
  out += "  \"materials\": {";
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    out += (i ? ",\n" : "\n") + material_json(scene.materials[i], names[i]);
  }
  out += scene.materials.empty() ? "},\n" : "\n  },\n";
  out += "  \"shapes\": [";
  for (size_t i = 0; i < scene.shapes.size(); ++i) {
    out += (i ? ",\n" : "\n") + shape_json(scene.shapes[i], i, scene.materials, names);
  }
  out += scene.shapes.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

}  // namespace tessera
