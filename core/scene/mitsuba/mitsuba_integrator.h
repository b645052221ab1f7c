// Mitsuba's <integrator> (docs/mitsuba.md, "Integrator").
#pragma once

#include <cstdint>
#include <string>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// What an integrator says about the image.
struct MitsubaIntegrator {
  /// Mitsuba's convention, which Tessera's render.max_depth shares: path segments including the
  /// camera ray, -1 unbounded (the default).
  int max_depth = -1;
  /// RenderSettings::rr_depth: where Russian roulette starts, as Tessera counts it.
  int rr_depth = kDefaultRrDepth;
  bool hide_emitters = false;
  /// `direct`: its `emitter_samples` as written (1 when absent, and for the others). With
  /// emitter_samples N > 1 Mitsuba 3.9.1's image of a delta light (point, spot, directional,
  /// projector) is N times too bright, whatever bsdf_samples (measured: N = 2, 3, 4 with
  /// bsdf_samples 0...4); `shading_samples` alone does not do it (3: 1x). The loader refuses
  /// that pair (docs/mitsuba.md, "Integrator").
  int64_t emitter_samples = 1;
  /// False for `volpath`: it does not count null interactions (a mask's or null BSDF's
  /// passage, a thindielectric's straight transmission) toward max_depth, as Mitsuba's path
  /// integrator and Tessera do. The loader refuses such materials with a finite max_depth.
  bool counts_null_interactions = true;
  /// `volpath` and `volpathmis` (also nested in `moment`): they render the scene's media;
  /// Mitsuba's other integrators ignore media (the loader then leaves them out).
  bool volumetric = false;
  /// `ptracer` (also nested in moment or aov): the loader adds to the note what of this scene
  /// Mitsuba's particle tracer leaves black (mitsuba_ptracer_note).
  bool particle_tracer = false;
  /// For an integrator Tessera renders as `path`: a line saying so ("" for path itself).
  std::string note;
};

/// What the image of Mitsuba's particle tracer (ptracer) lacks in `scene`, for the note of a
/// scene rendered by Tessera's path tracer in its place. The particle tracer connects each
/// surface it reaches to the camera by a shadow ray and the BSDF's value toward it: a smooth
/// (delta) lobe has none, and a see-through surface (null BSDF, mask, thindielectric's straight
/// transmission, polarizer) blocks the shadow ray. So what the camera sees on a smooth or
/// see-through surface, or through a chain of them, is black in Mitsuba (smooth plastic shows
/// its diffuse base only), and lit in Tessera. Names the materials of the scene's shapes that
/// are such surfaces (smooth dielectric, conductor, plastic, thindielectric, polarizer, masks,
/// null, and blends or two-sided backs holding one), or says the image is the same when none is.
std::string mitsuba_ptracer_note(const Scene& scene);

/// Reads an integrator whose image is the one Tessera's path tracer makes:
/// - `path`: max_depth, rr_depth, hide_emitters;
/// - `ptracer` (light tracing: other noise, and the same image but where the camera sees
///   smooth or see-through surfaces, mitsuba_ptracer_note): max_depth, rr_depth,
///   hide_emitters; samples_per_pass accepted;
/// - `volpath` and `volpathmis` (media/volpath.h renders their image; without media the same
///   as path): max_depth, rr_depth, hide_emitters; volpathmis's use_spectral_mis changes noise
///   only;
/// - `direct` (direct illumination only: path with max_depth 2): hide_emitters;
///   emitter_samples, bsdf_samples and shading_samples change noise only (but see
///   MitsubaIntegrator::emitter_samples).
/// - `direct_projective` (Mitsuba's projective-sampling integrator for gradients; its primal
///   image is `direct`'s, max_depth forced to 2): hide_emitters; max_depth and rr_depth checked
///   and ignored; its gradient options (sppc, sppp, sppi, guiding, guiding_proj,
///   guiding_rounds, project_seed) accepted, their enumerations checked.
/// - `moment`: its R, G, B are its first nested integrator's picture, read as that integrator
///   (any of the above); its AOV channels (X, Y, Z and second moments) are not written, and the
///   note says so.
/// rr_depth (> 0) says where Russian roulette starts, as in Mitsuba (path: from depth rr_depth
/// on; volpath, volpathmis and ptracer: past it); absent, Tessera's own start (kDefaultRrDepth),
/// since where it starts changes the noise, not the image; Tessera keeps its own survival
/// probability. Integrators that make another kind of image (stokes, depth, ...) or are not
/// Mitsuba 3.9.1's (prbvolpath's gradients) are refused, as are max_depth 0 or < -1 and
/// rr_depth <= 0, with SceneError naming the element.
MitsubaIntegrator read_mitsuba_integrator(const MitsubaElement& integrator,
                                          const MitsubaIds& ids);

}  // namespace tessera
