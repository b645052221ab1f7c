// Whether Mitsuba's near and far clip planes would change the image (docs/mitsuba.md).
#pragma once

#include <vector>

#include "scene/mitsuba/mitsuba_sensor.h"
#include "scene/scene.h"

namespace tessera {

/// Tessera's camera does not clip. Mitsuba's does: camera rays start at the plane local z =
/// near_clip and end at z = far_clip. The two agree exactly when no surface lies where a camera
/// ray could reach it before near_clip or beyond far_clip. This checks that: each triangle is
/// clipped against those two regions of the view cone (widened by the aperture for a thin
/// lens), each sphere is tested conservatively (it may be refused while in fact just outside).
/// Throws SceneError naming the sensor and the first shape that could be clipped. The cone is
/// the one of the sensor's own film size.
void check_mitsuba_clip_planes(const MitsubaSensor& sensor, const std::vector<Shape>& shapes);

}  // namespace tessera
