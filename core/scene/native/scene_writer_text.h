// Internal to write_scene_json (scene_writer.h), in namespace scene_writer: the JSON text it is
// made of (strings, numbers, vectors, matrices, blocks) and the names it gives textures,
// materials, groups and media.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace tessera::scene_writer {

/// `text` with bytes that are not UTF-8 replaced by '?': JSON text is UTF-8.
std::string valid_utf8(std::string_view text);

/// A JSON string literal of valid UTF-8 `text`.
std::string json_string(std::string_view text);

/// The shortest decimal that reads back as `x` (std::to_chars); -0 as "-0.0", which the JSON
/// reader takes as a double, keeping its sign (a bare "-0" reads as the integer 0).
std::string number(double x, const std::string& what);

std::string vec3(const glm::dvec3& v, const std::string& what);

/// A 4 x 4 matrix as {"matrix": rows}.
std::string matrix_json(const glm::dmat4& m, const std::string& what);

/// Names as written (of materials, textures, groups): valid UTF-8, non-empty and unique.
template <typename T>
std::vector<std::string> unique_names(const std::vector<T>& items, const char* fallback) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const T& m : items) {
    std::string base = valid_utf8(m.name);
    if (base.empty()) base = fallback;
    std::string name = base;
    for (int k = 2; used.count(name); ++k) name = base + " #" + std::to_string(k);
    used.insert(name);
    names.push_back(name);
  }
  return names;
}

const char* bool_text(bool b);

/// The names the JSON uses for textures, materials and groups.
struct Names {
  std::vector<std::string> textures, materials, groups, media;
};

/// The JSON string naming medium `index` (-1 = none, which the caller leaves out).
std::string medium_name(int32_t index, const Names& names, const std::string& what);

std::string texture_name(int32_t index, const Names& names, const std::string& what);

std::string textured_color(const TexturedColor& c, const Names& names, const std::string& what);

std::string textured_float(const TexturedFloat& f, const Names& names, const std::string& what);

/// `items` as the body of a JSON object ("{...}") or array ("[...]"), one per line.
template <typename F>
std::string block(size_t count, char open, char close, F item) {
  std::string out(1, open);
  for (size_t i = 0; i < count; ++i) out += (i ? ",\n" : "\n") + item(i);
  out += count ? "\n  " : "";
  return out + close;
}

}  // namespace tessera::scene_writer
