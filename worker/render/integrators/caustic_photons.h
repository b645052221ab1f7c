// Builds a scene's caustic guide (guiding/caustic_guide.h) from photons: from each light toward
// each specular target, through glass and mirrors with the path vertex's own functions
// (vertex_shading.h), to the first diffuse surface, where each photon deposits its power in the
// guide's cell and direction bin. Then each cell's share of the light one bounce gathers there.
// Deterministic: photon i draws its numbers from a hash of its index, and its deposit joins the
// others in index order, whatever thread traced it.
#pragma once

#include "render/guiding/caustic_guide.h"
#include "render/scene/traceable_scene.h"

namespace tessera {

/// The guide of `scene` (whose lights and specular targets are built): empty when the scene
/// has no targets, no lights, or media (the volumetric path tracer does not use the guide),
/// or no photon reached a diffuse surface through a target. Photons from a light at infinity
/// start on the plane tangent to the target on the light's side, where an occlusion test
/// toward the light says whether it reaches them. Runs on the caller's TBB arena.
CausticGuide build_caustic_guide(const TraceableScene& scene);

}  // namespace tessera
