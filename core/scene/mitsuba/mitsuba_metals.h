// Mitsuba's named conductors (the `material` parameter of conductor and roughconductor) as the
// RGB eta and k of its RGB variants.
#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace tessera {

struct MitsubaMetal {
  glm::dvec3 eta;  ///< real part of the complex index of refraction, per linear sRGB channel
  glm::dvec3 k;    ///< imaginary part (absorption)
};

/// The eta and k Mitsuba 3's RGB variants give conductor material `name` ("Au", "Cu", "Al",
/// ...; exact case, as Mitsuba), or nullopt for a name it does not know.
std::optional<MitsubaMetal> mitsuba_named_metal(std::string_view name);

/// The names mitsuba_named_metal knows, comma-separated, for messages.
std::string mitsuba_metal_names();

}  // namespace tessera
