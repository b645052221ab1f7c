// The volumetric path tracer: Mitsuba's volpath for scenes with participating media
// (docs/renderer.md, "Media"). Renderer uses it instead of trace_path (integrator.h) when the
// scene has a medium (TraceableScene::has_media), so a scene without one renders the same bits
// as before media existed and pays nothing for them.
#pragma once

#include <glm/vec3.hpp>

#include "render/integrators/integrator.h"
#include "render/math/ray.h"
#include "render/sampling/sampler.h"
#include "render/scene/traceable_scene.h"

namespace tessera {

/// Dimension pairs per event of a volumetric path (one closest-hit query and what follows it):
/// (channel, distance) of the free flight, (light choice, roulette), light point, direction
/// (phase or BSDF), (BSDF lobe, mask), and the key of the tracking streams (medium.h).
inline constexpr uint32_t kVolumePairsPerEvent = 6;
/// A path ends after this many events (closest-hit queries): only a path that crosses null
/// surfaces back and forth without end could get there, since every scattering event is
/// subject to Russian roulette.
inline constexpr uint32_t kMaxVolumeEvents = 100000;
/// A shadow ray passes through at most this many null surfaces (null BSDFs, masks,
/// thindielectric sheets) before it counts as blocked.
inline constexpr int kMaxShadowCrossings = 256;

/// Estimates the radiance arriving along the camera ray `ray` (unit direction) in a scene with
/// media, starting in the camera's medium. As Mitsuba's volpath: free flights in the current
/// medium (medium.h) end in a scattering event (next-event estimation weighed by MIS against
/// phase sampling, then a phase-sampled direction) or at the surface; surfaces are shaded as
/// trace_path shades them (next-event estimation and BSDF sampling with MIS), and a surface that
/// bounds a medium switches the path's medium by the side it leaves to. Null interactions (null
/// BSDFs and masks passed, a thindielectric's straight transmission) neither count toward
/// max_depth nor change the MIS state, as in Mitsuba's volpath; shadow rays pass through them,
/// weighed by their transmission, and through media, weighed by the transmittance. Russian
/// roulette from the scene's rr_depth-th scattering event on (the third by default), survival
/// min(max(beta) eta^2, 0.95).
/// Returns the estimate; NaN/Inf are left for the caller to count.
glm::dvec3 trace_volume_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                             PathCounters& counters);

}  // namespace tessera
