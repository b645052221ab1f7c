// What one camera sample gives the denoiser's guides: the albedo and shading normal of the
// first surface it meets that is not purely specular, followed through mirrors and smooth
// glass, as Open Image Denoise's documentation asks of its auxiliary images.
#pragma once

#include <glm/vec3.hpp>

#include "render/math/ray.h"
#include "render/sampling/sampler.h"
#include "render/scene/traceable_scene.h"

namespace tessera {

struct GuideSample {
  glm::vec3 albedo{0.0f};  ///< in [0, 1]
  glm::vec3 normal{0.0f};  ///< unit, world space, facing the ray; zero where nothing was hit
};

/// Delta-only surfaces a guide ray passes at most (a ray trapped by total internal reflection
/// ends there, with zero guides).
inline constexpr int kMaxGuideSpecularVertices = 8;

/// Follows the camera ray `ray` of `sampler`'s (pixel, sample) through surfaces with only delta
/// lobes (mirrors, smooth conductors and glass: the direction the BSDF samples with the colour
/// path's numbers for that vertex, so a glass's reflect-or-refract choice is the colour path's)
/// to the first surface with a non-delta lobe. Returns that surface's shading normal and its
/// albedo: one BSDF sample's weight (exact for Lambertian surfaces, an unbiased estimate of the
/// directional albedo otherwise), times the delta surfaces' tints on the way, clamped to
/// [0, 1]. Zero albedo and normal where the ray escapes or ends. Masks count as opaque;
/// media are ignored. A pure function of the scene, the ray and the sampler's (pixel, sample).
GuideSample trace_guide(const TraceableScene& scene, Ray ray, PixelSampler& sampler);

}  // namespace tessera
