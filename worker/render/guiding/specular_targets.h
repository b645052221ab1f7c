// Specular targets: the scene's purely specular shapes (smooth glass, thin glass, mirrors and
// smooth conductors), each bounded by a sphere, toward which a diffuse vertex sends some of its
// bounces (target_mixture.h; docs/renderer.md, "Bounces toward glass and mirrors"). Light that reaches a diffuse point only through such a shape (a caustic, what a
// mirror shows of a lamp) cannot be found by a shadow ray: only the bounce finds it, and a
// cosine-weighted bounce rarely points at a small sphere.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "render/guiding/test_switch.h"

namespace tessera {

struct Geometry;
struct RenderMaterial;

/// One target: a sphere bounding a purely specular shape, in world space.
struct SpecularTarget {
  glm::vec3 center{0.0f};
  float radius = 0;
};

/// The image of one emitter's bounding sphere formed by one target (a ball lens, a convex
/// mirror, a flat mirror face), in world space: the sphere (center, radius) the emitter's light
/// seems to come from, seen through the target. Used at a diffuse point x only where
/// dot(gate_normal, x) > gate_offset (x on the side where the target can carry the emitter's
/// light) and where the line from x through the image passes the window (the target's bounding
/// sphere, or a mirror face's). docs/renderer.md, "Bounces aimed at the lamps' images".
struct SpecularImage {
  glm::vec3 center{0.0f};
  float radius = 0;
  glm::vec3 gate_normal{0.0f};
  float gate_offset = 0;
  glm::vec3 window_center{0.0f};
  float window_radius = 0;
};

/// The targets of one scene, built once from it (TraceableScene) and read-only afterwards.
class SpecularTargets {
 public:
  /// At most this many targets: a diffuse vertex tests each one, so the cost per vertex is
  /// bounded; beyond it the largest spheres are kept (docs/renderer.md).
  static constexpr int kMaxTargets = 8;
  /// A shape whose bounding sphere's radius exceeds this fraction of the scene's bounding
  /// sphere's is left out: a glass box around everything, or a mirror wall, fills most of
  /// the hemisphere anyway, where the cosine-weighted bounce already finds it.
  static constexpr float kMaxSceneFraction = 0.5f;
  /// The rule for the probability of a bounce toward each target (TargetMixture::init): this
  /// factor times the target's share of the cosine-weighted bounce...
  static constexpr float kMassFactor = 1.0f;
  /// ... and at most this in all, so that the cosine keeps half of the bounces.
  static constexpr float kMaxTargetProbability = 0.5f;
  /// At most this many lamp images (emitter, target pairs): each costs a diffuse vertex a gate
  /// test, and a few dozen instructions where it passes. Beyond it the images with the largest
  /// score (the emitter's power times the fraction of it the target intercepts) are kept.
  static constexpr int kMaxImages = 8;
  /// An image's cone gets this many times its share of the cosine strategy (every image alike): it carries a
  /// lamp's radiance, where a bounding sphere's cone mostly shows what the glass refracts of
  /// the room (measured: docs/renderer.md).
  static constexpr float kImageMassFactor = 4.0f;
  /// The margin added to a ball lens's image radius for its spherical aberration, as a
  /// fraction of the lens's radius (measured: docs/renderer.md).
  static constexpr float kLensAberration = 0.1f;
  /// The margin added to a convex mirror's image radius, as a fraction of its radius: the
  /// Gaussian image moves off-axis by up to R sin(t/2) (1 - cos(t/2)) for a point at angle t
  /// from the lamp's axis, 0.21 R at the gate's 90 degrees.
  static constexpr float kMirrorAberration = 0.21f;
  /// A triangle mirror with at most this many triangles is a set of flat faces, each making
  /// its own image; a larger one (a tessellated sphere) is a convex mirror of its bounding
  /// sphere.
  static constexpr int kMaxFlatTriangles = 16;

  SpecularTargets() = default;
  /// The targets among `shapes` (each: its Geometry, already in world space except that an
  /// instance's shapes are passed with their instance's to_world) whose material in
  /// `materials` is purely specular. `scene_radius`: the radius of the scene's bounding sphere.
  /// While a DisabledForTest lives, there are no targets (tests that compare the mixture with
  /// the cosine alone). Nothing outside a test binary can switch it: no flag or environment
  /// variable reaches it, so every worker of a farm builds the same targets (the determinism
  /// contract, docs/design.md).
  struct ShapeRef {
    const Geometry* geometry;
    const glm::mat4* to_world;  ///< nullptr: the geometry is in world space
  };
  /// The emitters among `shapes` (those with emission) get images through the targets.
  SpecularTargets(const std::vector<ShapeRef>& shapes, const std::vector<RenderMaterial>& materials,
                  float scene_radius);

  using DisabledForTest = TestSwitch<SpecularTargets>::Off;

  bool empty() const { return count_ == 0; }
  int size() const { return count_; }
  /// Target i (0 <= i < size()), read back from lanes().
  SpecularTarget operator[](int i) const {
    return {glm::vec3(lanes_.cx[i], lanes_.cy[i], lanes_.cz[i]), lanes_.r[i]};
  }

  /// The targets, the only store of them: centres, radii and radii squared as arrays
  /// (TargetMixture::init reads them at every diffuse vertex; r^2 computed once here). Entries
  /// past size() have r2 = infinity, so that no point lies outside them.
  struct Lanes {
    alignas(32) float cx[kMaxTargets];
    alignas(32) float cy[kMaxTargets];
    alignas(32) float cz[kMaxTargets];
    alignas(32) float r2[kMaxTargets];
    alignas(32) float r[kMaxTargets];
  };
  const Lanes& lanes() const { return lanes_; }

  /// The flat faces of a triangle mirror (each: the world-space vertices of its triangles that
  /// share one plane), or none when it has more than kMaxFlatTriangles triangles (a curved
  /// mirror, modelled by its bounding sphere) or is no triangle mesh.
  static std::vector<std::vector<glm::vec3>> flat_faces(const Geometry& g, const glm::mat4* to_world);

  int image_count() const { return image_count_; }
  /// The lamp images, at most kMaxImages, largest score first.
  const SpecularImage* images() const { return images_; }

  /// Every source of a cone, the targets then the images, as arrays for TargetMixture::init,
  /// which takes four or eight at a time (float4.h) through one formula: a target is an image
  /// of itself (centre and radius its sphere's) with no gate (gate_offset -infinity), its own
  /// sphere as window (so never turned toward 2p - I: dot(d, e) = |d|^2), `always` set (the
  /// window test does not apply) and mass kMassFactor; an image has kImageMassFactor. r^2
  /// computed once here. Entries past count (to kSourceLanes) have gate_offset = +infinity (no
  /// point passes) and zeros elsewhere.
  static constexpr int kMaxSources = kMaxTargets + kMaxImages;
  /// The arrays' length: kMaxSources, and room for a block of eight starting at any source.
  static constexpr int kSourceLanes = kMaxSources + 8;
  struct ConeSources {
    int count = 0;  ///< size() + image_count()
    alignas(32) float cx[kSourceLanes], cy[kSourceLanes], cz[kSourceLanes];  ///< centre
    alignas(32) float r[kSourceLanes], r2[kSourceLanes];                     ///< radius, squared
    alignas(32) float gx[kSourceLanes], gy[kSourceLanes], gz[kSourceLanes];  ///< gate normal
    alignas(32) float gate_offset[kSourceLanes];
    alignas(32) float wx[kSourceLanes], wy[kSourceLanes], wz[kSourceLanes];  ///< window centre
    alignas(32) float wr[kSourceLanes];                                      ///< window radius
    alignas(32) float mass[kSourceLanes];      ///< kMassFactor or kImageMassFactor
    alignas(32) int32_t always[kSourceLanes];  ///< -1: a target (no window test), else 0
  };
  const ConeSources& cone_sources() const { return sources_; }

 private:
  int count_ = 0;
  Lanes lanes_ = empty_lanes();
  int image_count_ = 0;
  SpecularImage images_[kMaxImages];
  ConeSources sources_ = empty_sources();

  struct Candidate {
    SpecularTarget sphere;
    const Geometry* geometry;
    const glm::mat4* to_world;
    const RenderMaterial* material;
  };
  struct Lamp {
    SpecularTarget sphere;
    float power;  ///< luminance of the emission times the area (a score, not watts)
  };
  void build_images(const std::vector<Candidate>& targets, const std::vector<Lamp>& lamps);

  static Lanes empty_lanes();
  static ConeSources empty_sources();
  void build_sources();
};

/// Whether every lobe of `m` (and of its back material) is a delta: mirror, smooth conductor,
/// smooth glass and thin glass. Texture lookups change a delta lobe's colour, never its
/// direction, so textured ones count too.
bool purely_specular(const RenderMaterial& m, const std::vector<RenderMaterial>& materials);

/// The smallest-radius sphere Ritter's algorithm finds around `points` (two passes: a first
/// guess from the extremes along x, y and z, grown to take in every point; then the sphere of
/// the axis-aligned box if that is smaller). Empty input: radius 0 at the origin.
SpecularTarget bounding_sphere(const std::vector<glm::vec3>& points);

/// The image of the sphere (lamp, lamp_radius) formed by a ball lens (center, radius) of
/// index `ior` (interior over exterior; 1 = no lens: the lamp itself), by Gaussian optics: both
/// principal planes at the centre, focal length f = n R / (2 (n - 1)), image distance
/// d_i = f d / (d - f) on the far side (negative: a virtual image on the lamp's side), radius
/// |d_i| / d lamp_radius plus kLensAberration R. Gate: the far side of the lens's centre from
/// the lamp. Empty when the lamp's centre lies inside the lens, or within 0.1 % of the focal
/// distance (the image at infinity), or when anything is not finite.
std::optional<SpecularImage> ball_lens_image(glm::vec3 center, float radius, float ior, glm::vec3 lamp,
                                             float lamp_radius);

/// The Gaussian virtual image of the sphere (lamp, lamp_radius) in a convex mirror sphere
/// (center, radius): f = -R / 2 from the surface point facing the lamp, radius magnified plus
/// kMirrorAberration R. Gate: the lamp's side of the plane through the centre. Empty when the
/// lamp's centre lies inside the mirror's sphere or anything is not finite.
std::optional<SpecularImage> convex_mirror_image(glm::vec3 center, float radius, glm::vec3 lamp,
                                                 float lamp_radius);

/// The mirror image of the sphere (lamp, lamp_radius) through the plane of a flat mirror face
/// (its vertices `face`, all in one plane), radius lamp_radius. The face's normal is the one
/// toward the lamp; `inside`, a point of the shape the face bounds (its vertices' centroid),
/// must not lie in front of it (the lamp sees the face from outside). Gate: in front of the
/// plane. Window: the face's bounding sphere. Empty for a degenerate face (no area), a lamp
/// centre on or behind the plane, or anything not finite.
std::optional<SpecularImage> flat_mirror_image(const std::vector<glm::vec3>& face, glm::vec3 inside, glm::vec3 lamp,
                                               float lamp_radius);

}  // namespace tessera
