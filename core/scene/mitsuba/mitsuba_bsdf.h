// Mitsuba BSDFs as Tessera materials (docs/mitsuba.md, "BSDFs").
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/scene.h"

namespace tessera {

/// Reads one <bsdf> element:
/// - `diffuse`: `reflectance` as <rgb> or <float>, each channel in [0, 1] (default 0.5);
///   one-sided, as in Mitsuba;
/// - `conductor` with `material` "none" (Mitsuba's default): the perfect mirror, one-sided;
/// - `dielectric`: glass with ior = int_ior / ext_ior, each a number or a name of Mitsuba's
///   table (defaults "bk7" and "air");
/// - `twosided` around one diffuse or conductor: the same material, two-sided.
/// `specular_reflectance` / `specular_transmittance` are accepted only when 1 (the default).
/// Everything else is refused: SceneError naming the element and what Tessera supports. The
/// material's name is left empty (see MitsubaMaterials).
Material read_mitsuba_bsdf(const MitsubaElement& bsdf, const MitsubaIds& ids);

/// The materials of a Mitsuba scene as shapes ask for them: one per BSDF element (a BSDF named
/// by several shapes through <ref> is one material), in order of first use, each named after
/// its id (or its type and line when it has none), names made unique.
class MitsubaMaterials {
 public:
  explicit MitsubaMaterials(const MitsubaIds& ids) : ids_(ids) {}

  /// The index of the material of BSDF element `bsdf`, read on first use.
  uint32_t of(const MitsubaElement& bsdf);
  /// Mitsuba's material for a shape without a BSDF: diffuse, reflectance 0.5, one-sided.
  uint32_t default_material();
  /// The materials in index order; the table is empty afterwards.
  std::vector<Material> take();

 private:
  uint32_t add(Material material, std::string name);

  const MitsubaIds& ids_;
  std::vector<Material> materials_;
  std::map<const MitsubaElement*, uint32_t> index_of_;
  std::set<std::string> names_;
  std::optional<uint32_t> default_;
};

}  // namespace tessera
