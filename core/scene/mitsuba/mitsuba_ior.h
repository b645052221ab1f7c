// Mitsuba's table of named indices of refraction (include/mitsuba/render/ior.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace tessera {

/// The index of refraction Mitsuba 3 gives the material `name` ("bk7", "water", "air",
/// "acrylic glass", ...; any letter case), or nullopt for a name it does not know. Values at
/// about 589 nm, from Hecht, Optics, as in Mitsuba.
std::optional<double> mitsuba_named_ior(std::string_view name);

/// The names mitsuba_named_ior knows, comma-separated, for messages.
std::string mitsuba_ior_names();

}  // namespace tessera
