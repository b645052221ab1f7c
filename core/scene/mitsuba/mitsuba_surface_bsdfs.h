// Mitsuba's surface BSDFs (the BSDFs that wrap no other; docs/mitsuba.md, "BSDFs") as Tessera
// materials, each with Mitsuba 3's parameters and defaults (listed at MitsubaMaterials,
// mitsuba_bsdf.h, which reads the wrappers and blends around them). Each reader takes the
// parameters it knows from `plugin` and throws SceneError naming the element for a bad value.
#pragma once

#include <string_view>

#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/scene.h"

namespace tessera {

/// int_ior / ext_ior with Mitsuba's defaults for the BSDF.
double read_relative_ior(MitsubaPlugin& plugin, std::string_view interior_default);

Material read_diffuse(MitsubaPlugin& plugin, MitsubaTextures& textures);

Material read_conductor(MitsubaPlugin& plugin, MitsubaTextures& textures, bool rough);

Material read_dielectric(MitsubaPlugin& plugin, MitsubaTextures& textures, MaterialType type);

Material read_plastic(MitsubaPlugin& plugin, MitsubaTextures& textures, bool rough);

/// Mitsuba's principled: eta or specular (not both), the weights, the sampling rates.
Material read_principled(MitsubaPlugin& plugin, MitsubaTextures& textures);

/// Mitsuba's principledthin: the weights, diff_trans, eta, the four sampling rates.
Material read_principled_thin(MitsubaPlugin& plugin, MitsubaTextures& textures);

/// Mitsuba's pplastic, as its RGB variants render it.
Material read_pplastic(MitsubaPlugin& plugin, MitsubaTextures& textures);

/// Mitsuba's polarizer, as its RGB variants render it: only transmittance changes the image.
/// theta (any angle in degrees, a spectrum, float or texture) and polarizing (a boolean) act on
/// polarization alone, which RGB images do not carry: they are accepted (polarizing checked for
/// its type).
Material read_polarizer(MitsubaPlugin& plugin, MitsubaTextures& textures);

}  // namespace tessera
