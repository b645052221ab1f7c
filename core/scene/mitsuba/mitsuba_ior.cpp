#include "scene/mitsuba/mitsuba_ior.h"

#include <array>
#include <cctype>

namespace tessera {
namespace {

struct NamedIor {
  std::string_view name;
  double ior;
};

// Mitsuba 3's ior_data, in its order. Mitsuba stores them as floats; the decimal values are
// the ones written in its table.
// clang-format off
constexpr std::array<NamedIor, 23> kIors = {{
    // gases
    {"vacuum", 1.0},
    {"helium", 1.000036},
    {"hydrogen", 1.000132},
    {"air", 1.000277},
    {"carbon dioxide", 1.00045},
    // liquids
    {"water", 1.3330},
    {"acetone", 1.36},
    {"ethanol", 1.361},
    {"carbon tetrachloride", 1.461},
    {"glycerol", 1.4729},
    {"benzene", 1.501},
    {"silicone oil", 1.52045},
    {"bromine", 1.661},
    // solids
    {"water ice", 1.31},
    {"fused quartz", 1.458},
    {"pyrex", 1.470},
    {"acrylic glass", 1.49},
    {"polypropylene", 1.49},
    {"bk7", 1.5046},
    {"sodium chloride", 1.544},
    {"amber", 1.55},
    {"pet", 1.5750},
    {"diamond", 2.419},
}};
// clang-format on

}  // namespace

std::optional<double> mitsuba_named_ior(std::string_view name) {
  std::string lower(name);
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  for (const NamedIor& entry : kIors) {
    if (entry.name == lower) return entry.ior;
  }
  return std::nullopt;
}

std::string mitsuba_ior_names() {
  std::string names;
  for (const NamedIor& entry : kIors) {
    names += (names.empty() ? "" : ", ") + std::string(entry.name);
  }
  return names;
}

}  // namespace tessera
