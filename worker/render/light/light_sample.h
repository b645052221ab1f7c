// What sampling a light returns: the direction towards it, the radiance arriving along it and
// the density it was sampled with.
#pragma once

#include <glm/vec3.hpp>

#include "render/math/ray_offset.h"

namespace tessera {

/// What a light sample says, seen from a shading point `ref`.
struct LightSample {
  glm::vec3 wi{0.0f};  ///< unit, from ref towards the light
  float distance = 0;  ///< to the sampled point; +inf for environment and directional lights
  /// What arrives along -wi if unoccluded (point/spot: intensity / distance^2, with the spot's
  /// falloff), NOT divided by pdf.
  glm::vec3 radiance{0.0f};
  /// Solid-angle density w.r.t. ref, including the light-pick probability; for delta lights
  /// the pick probability alone. 0 = no contribution (radiance is then 0 too).
  float pdf = 0;
  bool delta = false;  ///< point, spot, directional: MIS does not apply
  /// Area lights: the sampled point with its error bound and front-facing normal, so that the
  /// shadow ray can end at offset_ray_origin(point, -wi). Point and spot lights: the light's
  /// position with a zero error bound (ng = -wi). Unused for environment and directional lights.
  SurfacePoint point{};
  /// LightSet::sample: the sum of the light picker's importances at ref (LightPicker::pick),
  /// for LightSet::pdf_area and pdf_environment from the same ref, which then weigh one light
  /// instead of all (the same bits); negative when not known (picking by power, no sample).
  /// With up to 4 lights (one vector of LightImportance) that saves nothing, and trace_path
  /// does not carry it (measured: 0.1 % more instructions on the benchmark scenes); an
  /// integrator that keeps path state in arrays may, for scenes of 5 to 16 lights.
  float pick_sum = -1.0f;
};

}  // namespace tessera
