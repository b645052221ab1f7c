// Specular targets: the scene's purely specular shapes (smooth glass, thin glass, mirrors and
// smooth conductors), each bounded by a sphere, toward which a diffuse vertex sends some of its
// bounces (target_mixture.h; docs/renderer.md, "Bounces toward glass and mirrors"). Light that reaches a diffuse point only through such a shape (a caustic, what a
// mirror shows of a lamp) cannot be found by a shadow ray: only the bounce finds it, and a
// cosine-weighted bounce rarely points at a small sphere.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace tessera {

struct Geometry;
struct RenderMaterial;

/// One target: a sphere bounding a purely specular shape, in world space.
struct SpecularTarget {
  glm::vec3 center{0.0f};
  float radius = 0;
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
  SpecularTargets(const std::vector<ShapeRef>& shapes, const std::vector<RenderMaterial>& materials,
                  float scene_radius);

  class DisabledForTest {
   public:
    DisabledForTest();
    ~DisabledForTest();
    DisabledForTest(const DisabledForTest&) = delete;
    DisabledForTest& operator=(const DisabledForTest&) = delete;
  };

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

 private:
  int count_ = 0;
  Lanes lanes_ = empty_lanes();

  static Lanes empty_lanes();
};

/// Whether every lobe of `m` (and of its back material) is a delta: mirror, smooth conductor,
/// smooth glass and thin glass. Texture lookups change a delta lobe's colour, never its
/// direction, so textured ones count too.
bool purely_specular(const RenderMaterial& m, const std::vector<RenderMaterial>& materials);

/// The smallest-radius sphere Ritter's algorithm finds around `points` (two passes: a first
/// guess from the extremes along x, y and z, grown to take in every point; then the sphere of
/// the axis-aligned box if that is smaller). Empty input: radius 0 at the origin.
SpecularTarget bounding_sphere(const std::vector<glm::vec3>& points);

}  // namespace tessera
