// Mitsuba's `hair` BSDF (src/bsdfs/hair.cpp) as a Tessera hair material (docs/mitsuba.md,
// "hair").
#pragma once

#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/scene.h"

namespace tessera {

/// Reads a <bsdf type="hair"> whose int_ior / ext_ior the caller read as `eta` (Mitsuba's
/// defaults: amber over air), with Mitsuba's parameters, defaults and checks:
/// eumelanin (1.3) and pheomelanin (0.2), or sigma_a (a colour >= 0 or a texture, unbounded)
/// times scale (1; read always, as Mitsuba does, and applied to sigma_a only), not both;
/// longitudinal_roughness and azimuthal_roughness (0.3, each in [0, 1]); scale_tilt (2,
/// degrees). int_ior == ext_ior is refused, as Mitsuba refuses it. Throws SceneError naming the
/// property's line.
Material read_hair(MitsubaPlugin& plugin, MitsubaTextures& textures, double eta);

}  // namespace tessera
