// A participating medium as the volumetric path tracer samples it (docs/renderer.md, "Media"):
// free-flight distances and transmittance, in RGB without bias.
//
// RGB extinction differs per channel, so no one distance density fits all three. A homogeneous
// medium draws the distance by one channel, chosen uniformly by the sampler, and weighs the
// sample by the balance heuristic over the three channels' densities (one-sample MIS: the
// weight divides by the mean of the three densities, not by the chosen one's, so a channel
// whose extinction differs from the chosen one's never gets an unbounded weight). A
// heterogeneous one tracks against one majorant for all channels (delta tracking) and decides
// real or null collisions with the channels' mean extinction (spectral tracking, Kutz et al.
// 2017, with the mean instead of a hero channel): every channel then sees the same tentative
// collisions, and the weights stay bounded because the majorant bounds every channel.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "render/media/phase.h"
#include "render/sampling/sampler.h"
#include "render/texture/texture_set.h"
#include "scene/scene.h"

namespace tessera {

/// A stream of independent uniforms from one 64-bit key (SplitMix64): the inner loops of delta
/// and ratio tracking take a varying count of numbers, so they draw from a stream keyed by one
/// of the sampler's pairs instead of from pairs of their own; still a pure function of (seed,
/// pixel, sample index, dimension).
class TrackingStream {
 public:
  explicit TrackingStream(uint64_t key) : state_(key) {}
  float next() {
    state_ += PixelSampler::kIndependentStep;
    return to_unit_float(uint32_t(splitmix64(state_) >> 32));
  }

 private:
  uint64_t state_;
};

/// What a free flight found before the surface at t_max.
struct FreeFlight {
  bool scattered = false;  ///< a real scattering event at `t` (else the ray reached t_max)
  float t = 0;
  /// The path's throughput factor: (sigma_s Tr / pdf) at a scattering event, (Tr / P) at the
  /// surface; 0 when the flight ends the path (nothing can reach the surface).
  glm::dvec3 weight{1.0};
};

struct RenderMedium {
  MediumKind kind = MediumKind::homogeneous;
  /// Extinction (scale included) and albedo; where a texture gives them (heterogeneous sigma_t,
  /// any albedo): the factors the textures multiply.
  glm::vec3 sigma_t{0.0f};
  glm::vec3 albedo{0.0f};
  int32_t sigma_t_texture = -1, albedo_texture = -1;
  /// heterogeneous: the largest extinction anywhere in any channel (delta tracking's rate).
  float majorant = 0;
  /// heterogeneous with a sigma_t grid: the world-to-grid map; the medium is empty outside the
  /// grid's [0, 1]^3, as Mitsuba's heterogeneous medium is outside its sigma_t volume's bbox.
  bool bounded = false;
  glm::mat4 world_to_grid{1.0f};
  PhaseFunction phase;
  bool sample_emitters = true;

  /// Samples a free flight along o + t d (d unit) for t in [0, t_max) (t_max may be infinite).
  /// `u_channel`, `u_distance`: the sampler's pair for the flight (homogeneous); `stream`: the
  /// numbers of delta tracking (heterogeneous).
  FreeFlight sample_flight(glm::vec3 o, glm::vec3 d, float t_max, float u_channel, float u_distance,
                           TrackingStream& stream, const TextureSet& textures) const;

  /// The transmittance along o + t d for t in [0, t_max): closed form when homogeneous, ratio
  /// tracking (unbiased, from `stream`) when heterogeneous.
  glm::dvec3 transmittance(glm::vec3 o, glm::vec3 d, float t_max, TrackingStream& stream,
                           const TextureSet& textures) const;

  /// Extinction and albedo at world point p (heterogeneous lookups; constants otherwise).
  glm::vec3 sigma_t_at(glm::vec3 p, const TextureSet& textures) const;
  glm::vec3 albedo_at(glm::vec3 p, const TextureSet& textures) const;

 private:
  /// The part [t0, t1) of [0, t_max) inside the grid (all of it when not bounded); false when
  /// the ray misses the grid.
  bool clip(glm::vec3 o, glm::vec3 d, float t_max, float* t0, float* t1) const;
};

/// The render form of `m`; `textures` are the scene's (for the grids' maxima).
RenderMedium make_render_medium(const Medium& m, const std::vector<Texture>& textures);

/// exp(-sigma * t) per channel, 1 where sigma is 0 (also for t = infinity, where the product
/// would be NaN).
inline glm::dvec3 homogeneous_transmittance(glm::vec3 sigma, double t) {
  glm::dvec3 tr;
  for (int c = 0; c < 3; ++c) tr[c] = sigma[c] > 0 ? std::exp(-double(sigma[c]) * t) : 1.0;
  return tr;
}

/// The free-flight density of a homogeneous medium at distance t when the channel is chosen
/// uniformly: the mean over the channels of sigma_c exp(-sigma_c t) (balance heuristic).
inline double homogeneous_flight_pdf(glm::vec3 sigma, double t) {
  const glm::dvec3 tr = homogeneous_transmittance(sigma, t);
  return (double(sigma.x) * tr.x + double(sigma.y) * tr.y + double(sigma.z) * tr.z) / 3.0;
}

}  // namespace tessera
