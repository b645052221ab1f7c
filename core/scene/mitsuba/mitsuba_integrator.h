// Mitsuba's <integrator> (docs/mitsuba.md, "Integrator").
#pragma once

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_xml_document.h"

namespace tessera {

/// Reads a `path` integrator and returns its max_depth (Mitsuba's convention, which Tessera's
/// render.max_depth shares: path segments including the camera ray, -1 unbounded, the
/// default). rr_depth is accepted and ignored: Tessera's Russian roulette (from the third
/// bounce) is unbiased too, so where it starts changes the noise, not the image. hide_emitters
/// is accepted when false; true is refused. Other integrators and max_depth 0 or < -1 are
/// refused with SceneError naming the element.
int read_mitsuba_integrator(const MitsubaElement& integrator, const MitsubaIds& ids);

}  // namespace tessera
