// Mitsuba's emitters (docs/mitsuba.md, "Emitters"): area emitters on shapes, and the lights
// that are not shapes.
#pragma once

#include <optional>

#include "scene/mitsuba/mitsuba_file_resolver.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// An area emitter's radiance: constant, or scale * texture.
struct MitsubaAreaEmission {
  glm::dvec3 radiance{0};
  int32_t texture = -1;  ///< index into Scene::textures, -1 = constant
};

/// Reads <emitter type="area">: radiance (<rgb>, <float>, <spectrum> or a texture; default 1,
/// as Mitsuba's RGB variants); sampling_weight is accepted (it changes noise only). Throws
/// SceneError naming the element for another type or parameter.
MitsubaAreaEmission read_mitsuba_area_emitter(const MitsubaElement& emitter, const MitsubaIds& ids,
                                              MitsubaTextures& textures);

/// Reads an emitter that is not on a shape:
/// - `point`: position or to_world (a translation), intensity (1);
/// - `spot`: to_world (rigid; it shines along local +z), intensity (1), cutoff_angle (20),
///   beam_width (3/4 of cutoff_angle), texture (a <texture>, read into `textures`, projected
///   over the cone: Light::texture);
/// - `directional`: direction or to_world (+z), irradiance (1);
/// - `constant`: radiance (1);
/// - `projector`: to_world (rigid; it projects along local +z), irradiance (<rgb>, <float>,
///   <spectrum> or a <texture>; 1), scale (1), fov with fov_axis or focal_length (50mm) for an
///   image of the texture's aspect (a bitmap's width / height, read from its file; 1 otherwise);
/// - `envmap`: filename (a lat-long EXR, HDR or other image, looked up as Mitsuba does and added
///   to `referenced_files`), scale (1), to_world (rigid); mis_compensation is accepted (noise
///   only).
/// Every one accepts sampling_weight. Colours take <rgb>, <float> or <spectrum> (emission:
/// Mitsuba's RGB conversion without D65), each channel >= 0. Throws SceneError naming the
/// element for an area emitter (it belongs inside a <shape>), another type or parameter.
Light read_mitsuba_light(const MitsubaElement& emitter, const MitsubaIds& ids,
                         MitsubaFileResolver& files, std::vector<std::string>& referenced_files,
                         MitsubaTextures& textures);

}  // namespace tessera
