// Mitsuba's <spectrum> values as the linear sRGB colours of its RGB variants (docs/mitsuba.md,
// "Colours and spectra").
#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace tessera {

/// What a colour parameter is, which decides how Mitsuba turns a spectrum into RGB.
enum class MitsubaColorRole {
  reflectance,  ///< bounded to [0, 1], seen under D65 (Mitsuba's default for textures)
  unbounded,    ///< >= 0, seen under D65: indices of refraction (eta, k)
  emission,     ///< >= 0, an emitter's own power: no D65 weighting
};

/// The linear sRGB colour of spectrum `value` in Mitsuba 3's RGB variants
/// (src/core/properties.cpp, spectrum_list_to_srgb):
/// - one number v: (v, v, v), except for emission, where Mitsuba keeps a flat spectrum's colour
///   v * xyz_to_srgb(1, 1, 1) (slightly purple: sRGB's white is D65, not flat);
/// - "w1:v1, w2:v2, ..." (nanometres, strictly increasing, at least two pairs): the piecewise
///   linear spectrum integrated against the CIE 1931 colour matching functions (times D65 unless
///   emission) at Mitsuba's 1000 steps over 360-830 nm, to sRGB, clamped to [0, 1]
///   (reflectance) or to >= 0.
/// Returns nullopt with `error` set when the text is neither.
std::optional<glm::dvec3> mitsuba_spectrum_to_rgb(std::string_view value, MitsubaColorRole role,
                                                  std::string& error);

}  // namespace tessera
