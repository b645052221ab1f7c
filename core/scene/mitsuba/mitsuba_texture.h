// Mitsuba's <texture> plugins and the textured parameters that use them (docs/mitsuba.md,
// "Textures").
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene/mitsuba/mitsuba_file_resolver.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_spectrum.h"
#include "scene/scene.h"

namespace tessera {

/// The textures of a Mitsuba scene, one per <texture> element (one named by several parameters
/// through <ref> is one texture), in order of first use.
class MitsubaTextures {
 public:
  /// `ids`, `files` and `referenced_files` must outlive this.
  MitsubaTextures(const MitsubaIds& ids, MitsubaFileResolver& files,
                  std::vector<std::string>& referenced_files)
      : ids_(ids), files_(files), referenced_files_(referenced_files) {}

  /// The index in Scene::textures of texture element `texture`, read on first use:
  /// - `bitmap`: filename (looked up as Mitsuba does, and added to the referenced files),
  ///   filter_type (bilinear, nearest), wrap_mode (repeat, mirror, clamp), raw (8/16-bit images
  ///   are sRGB-decoded unless raw; EXR, HDR and PFM are linear), to_uv; `accel` and `format`
  ///   change no pixel and are accepted;
  /// - `checkerboard`: color0, color1 (<rgb>, <float> or <spectrum>; defaults 0.4 and 0.2),
  ///   to_uv.
  /// - `rawconstant`: value (a <float> or a <vector>), used as written;
  /// - `mesh_attribute`: name ("vertex_..." or "face_..."), scale (1); whether the shapes have
  ///   the attribute is checked once the scene is read (check_mesh_attribute_use);
  /// - `volume`: a nested <volume name="volume">, gridvolume (filename: a .vol grid of 1 or 3
  ///   channels, read and checked here; filter_type trilinear or nearest; wrap_mode clamp,
  ///   repeat or mirror; to_world; use_grid_bbox; raw, accel and max_value change no lookup)
  ///   or constvolume (value: <float>, <rgb> or <spectrum>, default 1, unbounded as in
  ///   Mitsuba); without one it is refused (Mitsuba 3.9.1 refuses a <float> or <rgb> there and
  ///   crashes without any). Where it is used is checked once the scene is read
  ///   (check_volume_texture_use).
  /// Throws SceneError naming the element for another kind or parameter.
  int32_t of(const MitsubaElement& texture);
  /// The index of a bare <volume> element (gridvolume or constvolume, read as the nested
  /// volume of a `volume` texture above) as a TextureKind::volume texture: a heterogeneous
  /// medium's sigma_t or albedo. Read on first use.
  int32_t of_volume(const MitsubaElement& volume);

  /// The texture of index `index` (a value `of` returned), until take().
  const Texture& at(int32_t index) const { return textures_.at(size_t(index)); }

  /// The textures in index order; the table is empty afterwards.
  std::vector<Texture> take();

 private:
  Texture read(const MitsubaElement& element);
  /// Names `texture` after `element` (its id, else its type and line), keeps it, returns its index.
  int32_t add(const MitsubaElement& element, Texture texture);

  const MitsubaIds& ids_;
  MitsubaFileResolver& files_;
  std::vector<std::string>& referenced_files_;
  std::vector<Texture> textures_;
  std::map<const MitsubaElement*, int32_t> index_of_;
  std::set<std::string> names_;
};

/// Colour parameter `name` of `plugin`: a constant (<rgb>, <float>, <spectrum> read for `role`)
/// or a nested or referenced <texture>; `fallback` when absent. Constants of the reflectance
/// role must be in [0, 1], the others >= 0 (SceneError naming the property otherwise).
TexturedColor read_textured_color(MitsubaPlugin& plugin, std::string_view name,
                                  const glm::dvec3& fallback, MitsubaColorRole role,
                                  MitsubaTextures& textures);

/// Scalar parameter `name`: a <float>, an <rgb> (Mitsuba's sRGB texture: each channel in [0, 1],
/// the mean of the three) or a texture (its lookups give the first channel, or the mean of an
/// RGB texture); `fallback` when absent.
TexturedFloat read_textured_float(MitsubaPlugin& plugin, std::string_view name, double fallback,
                                  MitsubaTextures& textures);

/// Mitsuba's `to_uv` (a <transform>, of which the x and y rows and the translation act on
/// (u, v)) as the 3x3 matrix M with (u', v', 1) = M (u, v, 1) (glm's column-major layout:
/// M[2] holds the translation).
glm::dmat3 read_mitsuba_to_uv(MitsubaPlugin& plugin);

}  // namespace tessera
