// Mitsuba BSDFs as Tessera materials (docs/mitsuba.md, "BSDFs").
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// The materials of a Mitsuba scene as shapes ask for them: one per BSDF element (a BSDF named
/// by several shapes through <ref> is one material), in order of first use, each named after
/// its id (or its type and line when it has none), names made unique.
///
/// The BSDFs, with Mitsuba 3's parameters, defaults and meaning (colour parameters take
/// <rgb>, <float>, <spectrum> or a texture, unless said otherwise):
/// - `diffuse`: reflectance (0.5);
/// - `conductor`, `roughconductor`: material (a name of Mitsuba's table, or "none", the
///   default: a perfect mirror unless eta or k is given), or eta (0) and k (1) as constants;
///   specular_reflectance (1); rough: distribution (beckmann, ggx), alpha or alpha_u/alpha_v
///   (0.1, textured), sample_visible (true). A smooth perfect conductor with no tint is the
///   `mirror` material;
/// - `dielectric`, `roughdielectric`, `thindielectric`: int_ior (bk7), ext_ior (air), each a
///   number or a name of Mitsuba's table; specular_reflectance, specular_transmittance (1);
///   rough: as roughconductor;
/// - `plastic`, `roughplastic`: diffuse_reflectance (0.5), specular_reflectance (1), int_ior
///   (polypropylene), ext_ior (air), nonlinear (false); rough: distribution (beckmann), alpha
///   (0.1, textured), sample_visible;
/// - `principled`: base_color (0.5), roughness (0.5), anisotropic, metallic, spec_trans,
///   spec_tint, sheen, sheen_tint, flatness, clearcoat, clearcoat_gloss (0; each a float in
///   [0, 1] or a texture), eta or specular (0.5; not both; Mitsuba's conversion
///   eta = 2 / (1 - sqrt(0.08 specular)) - 1), main_specular_sampling_rate,
///   clearcoat_sampling_rate, diffuse_reflectance_sampling_rate (1). With spec_trans it
///   transmits light and is two-sided by nature;
/// - `pplastic` (as Mitsuba's RGB variants render it, without polarization):
///   diffuse_reflectance (0.5), specular_reflectance (1), eta (a float or texture) or int_ior
///   (polypropylene) / ext_ior (air), not both; distribution (beckmann), alpha or alpha_u /
///   alpha_v (0.1, textured), sample_visible;
/// - `principledthin`: base_color (0.5), roughness (0.5), anisotropic, spec_trans, spec_tint,
///   sheen, sheen_tint, flatness (0; each a float in [0, 1] or a texture), diff_trans (0; a
///   float in [0, 2] or a texture), eta (1.5; a float or a texture), and the sampling rates
///   diffuse_reflectance_, specular_reflectance_, specular_transmittance_ and
///   diffuse_transmittance_sampling_rate (1). Two-sided by nature, as a dielectric;
/// - `polarizer` (as Mitsuba's RGB variants render it, without polarization): transmittance
///   (1; colour or texture): light passes straight through from either side, times
///   transmittance / 2; theta and polarizing are accepted and change no RGB image;
/// - `blendbsdf`: weight (required; a float, clamped to [0, 1] as Mitsuba does, or a texture)
///   and two nested BSDFs, which may be blends but have no twosided, mask, bumpmap or normalmap
///   inside (those go around the blend);
/// - `twosided` around one BSDF (the same on both sides) or two (front, back); the nested BSDFs
///   must not transmit light, as in Mitsuba;
/// - `mask` around one BSDF: opacity (0.5, textured);
/// - `bumpmap` around one BSDF: one nested texture (the height field), scale (1);
/// - `normalmap` around one BSDF: the nested texture `normalmap`.
/// Everything else is refused: SceneError naming the element and what Tessera supports. A BSDF
/// that contains itself through <ref>s (`<bsdf type="twosided" id="a"><ref id="a"/></bsdf>`, or
/// a -> b -> a) is refused naming the cycle, before any recursion could run out of stack.
class MitsubaMaterials {
 public:
  /// `ids` and `textures` must outlive this.
  MitsubaMaterials(const MitsubaIds& ids, MitsubaTextures& textures)
      : ids_(ids), textures_(textures) {}

  /// The index of the material of BSDF element `bsdf`, read on first use.
  uint32_t of(const MitsubaElement& bsdf);
  /// Mitsuba's material for a shape without a BSDF: diffuse, reflectance 0.5, one-sided; for
  /// a shape with an area emitter (`emitter` true) diffuse with reflectance 0, as Mitsuba 3's
  /// Shape gives it: such a light reflects nothing, on either side.
  uint32_t default_material(bool emitter = false);
  /// The materials in index order; the table is empty afterwards.
  std::vector<Material> take();

 private:
  uint32_t add(Material material, const MitsubaElement& bsdf);
  uint32_t add_named(Material material, const std::string& name);
  Material read(const MitsubaElement& bsdf);
  Material read_plugin(const MitsubaElement& bsdf);
  Material read_twosided(MitsubaPlugin& plugin);
  Material read_blend(MitsubaPlugin& plugin);
  Material read_wrapper(MitsubaPlugin& plugin);

  const MitsubaIds& ids_;
  MitsubaTextures& textures_;
  std::vector<Material> materials_;
  std::map<const MitsubaElement*, uint32_t> index_of_;
  std::set<std::string> names_;
  std::optional<uint32_t> default_;
  std::optional<uint32_t> default_emitter_;
  /// The BSDFs being read, outermost first: a nested BSDF already on it closes a cycle.
  std::vector<const MitsubaElement*> reading_;
};

}  // namespace tessera
