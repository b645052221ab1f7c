// Mitsuba's <sensor> with its <film>, <rfilter> and <sampler> (docs/mitsuba.md, "Sensors").
#pragma once

#include <cstdint>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"
#include "scene/transform.h"

namespace tessera {

/// What a sensor says about the image.
struct MitsubaSensor {
  Camera camera;
  Film film{768, 576, {}};  ///< Mitsuba's hdrfilm defaults (read_film sets the filter)
  int64_t spp = 4;          ///< the sampler's sample_count (Mitsuba's default sampler: 4)
  uint64_t seed = 0;        ///< the sampler's seed
  double near_clip = 1e-2;  ///< scene units along the view axis (Mitsuba's defaults)
  double far_clip = 1e4;
  /// The sensor's to_world: rigid for perspective and thinlens; for orthographic a rotation of
  /// a positive scale (the scale sets the view size) and a translation.
  Transform camera_to_world;
  const MitsubaElement* element = nullptr;  ///< the <sensor>, for messages
  /// The <medium> the camera sits in (nested or through <ref>), nullptr = vacuum.
  const MitsubaElement* medium = nullptr;
};

/// Reads a `perspective`, `thinlens` or `orthographic` sensor. Its to_world is the camera frame: Mitsuba's
/// camera looks down its local +z with +y up and image x running along local -x, so the
/// camera's position, look_at and up are the images of the local origin, of (0, 0, 1) and of
/// +y; to_world must be a rotation and translation (Mitsuba refuses scale, and a mirror would
/// flip the image, which Tessera's camera cannot).
///
/// - fov with fov_axis x, y, smaller, larger or diagonal (kept as the diagonal: the camera
///   turns it into the horizontal angle for the image's aspect, as Mitsuba's parse_fov does for
///   its film's), or focal_length (Mitsuba's default 50mm: a diagonal angle);
/// - thinlens: aperture_radius (required, >= 0) and focus_distance (> 0; default far_clip, as
///   in Mitsuba); perspective: focus_distance is accepted and ignored (a pinhole has no focus);
/// - near_clip and far_clip are kept for check_mitsuba_clip_planes;
/// - orthographic: to_world = lookat * scale (no shear, no mirror); the view covers local
///   x in [-1, 1] and y in [-1, 1] / aspect, so view_size = (2 sx, 2 sy / aspect); rays start
///   at local z = near_clip, where the camera's position is put (an exact near clip); fov, lens
///   and principal point parameters are not Mitsuba's for this sensor (unknown, so refused);
/// - principal_point_offset_x/y accepted only at 0; shutter_open/close ignored (nothing moves);
/// - one <film type="hdrfilm">: width, height (in [1, 32768]), pixel_format rgb or rgba,
///   component_format and file_format (the output's format is chosen by `-o`), sample_border
///   (no effect with a box filter), crop_* only when they cover the whole image; it must hold
///   <rfilter type="box"/> (Mitsuba's default, gaussian, blurs: refused);
/// - at most one <sampler> (independent, stratified, multijitter, orthogonal, ldsampler; Tessera
///   uses its own sequence): sample_count, seed; jitter and strength ignored.
/// Throws SceneError naming the element for anything else.
MitsubaSensor read_mitsuba_sensor(const MitsubaElement& sensor, const MitsubaIds& ids);

/// Mitsuba's parse_fov for an image of width / height `aspect`: fov with fov_axis (x, y,
/// smaller, larger, diagonal), or focal_length (default "50mm", a 35 mm film's diagonal), as
/// the horizontal field of view in degrees, in (0, 180). Takes those properties from `plugin`
/// (a sensor, or the projector emitter, which frames its image the same way). Throws
/// SceneError naming the property otherwise.
double read_mitsuba_fov_x(MitsubaPlugin& plugin, double aspect);

}  // namespace tessera
