#include "scene/native/scene_writer_text.h"

#include <charconv>
#include <cmath>
#include <glm/gtc/matrix_access.hpp>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"

namespace tessera::scene_writer {

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

}  // namespace

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

std::string matrix_json(const glm::dmat4& m, const std::string& what) {
  std::string out = "{\"matrix\": [";
  for (int r = 0; r < 4; ++r) {
    out += r ? ", [" : "[";
    for (int c = 0; c < 4; ++c) out += (c ? ", " : "") + number(m[c][r], what);
    out += "]";
  }
  return out + "]}";
}

const char* bool_text(bool b) { return b ? "true" : "false"; }

std::string medium_name(int32_t index, const Names& names, const std::string& what) {
  if (index < 0 || size_t(index) >= names.media.size()) {
    throw SceneError(what + ": medium index out of range");
  }
  return json_string(names.media[size_t(index)]);
}

std::string texture_name(int32_t index, const Names& names, const std::string& what) {
  if (index < 0 || size_t(index) >= names.textures.size()) {
    throw SceneError(what + ": texture index out of range");
  }
  return json_string(names.textures[index]);
}

std::string textured_color(const TexturedColor& c, const Names& names, const std::string& what) {
  if (c.is_constant()) return vec3(c.value, what);
  return "{\"texture\": " + texture_name(c.texture, names, what) +
         ", \"scale\": " + vec3(c.value, what) + "}";
}

std::string textured_float(const TexturedFloat& f, const Names& names, const std::string& what) {
  if (f.is_constant()) return number(f.value, what);
  return "{\"texture\": " + texture_name(f.texture, names, what) +
         ", \"scale\": " + number(f.value, what) + "}";
}

}  // namespace tessera::scene_writer
