#include "scene/mesh/ply_attributes.h"

#include <array>
#include <cmath>
#include <set>
#include <string>

namespace tessera {
namespace {

/// Mitsuba's postfix categories: column k of row j is the j-th channel of category k.
constexpr std::array<std::string_view, 4> kPostfixes = {"xr01", "yg12", "zb23", "wa34"};

double integer_max(PlyType type) {
  switch (type) {
    case PlyType::int8: return 127.0;
    case PlyType::uint8: return 255.0;
    case PlyType::int16: return 32767.0;
    case PlyType::uint16: return 65535.0;
    case PlyType::int32: return 2147483647.0;
    case PlyType::uint32: return 4294967295.0;
    default: return 1.0;
  }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1), as Mitsuba's Gamma flag applies it.
double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Properties r, g, b (or red, green, blue): "<kind>color", unless alpha is there too.
void add_color(const PlyElement& element, std::string_view kind, std::vector<bool>& used,
               PlyAttributeLayout& layout) {
  std::array<int, 4> rgba{};
  const std::array<std::array<const char*, 4>, 2> names = {
      {{"r", "g", "b", "a"}, {"red", "green", "blue", "alpha"}}};
  for (const auto& set : names) {
    for (int c = 0; c < 4; ++c) rgba[c] = element.find(set[c]);
    if (rgba[0] >= 0 && rgba[1] >= 0 && rgba[2] >= 0) break;
  }
  for (int c = 0; c < 4; ++c) {
    if (rgba[c] >= 0) used[rgba[c]] = true;  // reserved, as in Mitsuba, whatever happens below
  }
  if (rgba[0] < 0 || rgba[1] < 0 || rgba[2] < 0 || rgba[3] >= 0) return;
  for (int c = 0; c < 3; ++c) {
    if (element.properties[rgba[c]].is_list) return;
  }
  layout.attributes.push_back({std::string(kind) + "color", 3, {}});
  for (int c = 0; c < 3; ++c) {
    layout.slots[rgba[c]] = {int(layout.attributes.size() - 1), c};
  }
}

}  // namespace

PlyAttributeLayout ply_attribute_layout(const PlyElement& element, std::string_view kind,
                                        const std::vector<bool>& reserved) {
  PlyAttributeLayout layout;
  const size_t n = element.properties.size();
  layout.slots.assign(n, {});
  std::vector<bool> skip = reserved;
  skip.resize(n, false);
  for (size_t i = 0; i < n; ++i) skip[i] = skip[i] || element.properties[i].is_list;
  add_color(element, kind, skip, layout);

  std::set<std::string> seen;
  std::string prefix;
  std::vector<size_t> fields;  // the properties of the attribute being read
  size_t category = 0;
  auto flush = [&] {
    if (fields.size() == 1 || fields.size() == 3) {
      std::string name = std::string(kind) + prefix + (category == 1 ? "_color" : "");
      layout.attributes.push_back({name, int(fields.size()), {}});
      for (size_t c = 0; c < fields.size(); ++c) {
        layout.slots[fields[c]] = {int(layout.attributes.size() - 1), int(c)};
      }
    }
    if (!fields.empty()) seen.insert(prefix);
    fields.clear();
  };
  for (size_t i = 0; i < n; ++i) {
    if (skip[i]) continue;
    const std::string& name = element.properties[i].name;
    const size_t pos = name.find_last_of('_');
    if (pos == std::string::npos || pos + 2 != name.size()) {
      flush();
      continue;
    }
    const std::string p = name.substr(0, pos);
    const char c = name.back();
    if (!fields.empty() && p != prefix) flush();
    if (fields.empty()) {
      if (seen.count(p)) continue;
      const size_t k = kPostfixes[0].find(c);
      if (k == std::string_view::npos) continue;
      prefix = p;
      category = k;
      fields.push_back(i);
    } else if (fields.size() < kPostfixes.size() && kPostfixes[fields.size()][category] == c) {
      fields.push_back(i);
    } else {
      fields.assign(5, 0);  // a broken sequence: the whole attribute is left out
      flush();
    }
  }
  flush();
  return layout;
}

float ply_attribute_value(double value, PlyType type) {
  if (!ply_type_is_integer(type)) return float(value);
  return float(srgb_to_linear(value / integer_max(type)));
}

}  // namespace tessera
