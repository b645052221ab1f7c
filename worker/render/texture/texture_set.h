// Every texture of a scene, ready for lookups.
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "bitmap_texture.h"
#include "checkerboard.h"
#include "mesh_attribute_table.h"
#include "raw_constant.h"
#include "volume_texture.h"
#include "scene/file_reader.h"
#include "scene/scene.h"

namespace tessera {

/// Every texture of a scene, ready for lookups; built once per job, then read by many threads
/// (all lookups are const and touch only immutable data). Lookups follow Mitsuba 3 (see
/// BitmapTexture and Checkerboard) and are deterministic: the same bits on every machine.
///
/// Bitmaps are decoded once into texel arrays this set owns rather than served by
/// OpenImageIO's TextureSystem: Mitsuba sRGB-decodes every texel before it
/// interpolates, while the TextureSystem of OpenImageIO 2.4 filters the stored 8-bit codes and
/// has no per-texel colour decoding; its bilinear weights, wrap modes and derivatives are not
/// Dr.Jit's either. Mitsuba has no ray differentials, so the TextureSystem's MIP-mapping would
/// not be used: a lookup at zero footprint of the finest level is what matches it.
class TextureSet {
 public:
  /// An empty set.
  TextureSet() = default;

  /// Opens the scene's textures; bitmap files are read through `reader` (bundle paths, the
  /// FileReader of core/scene/file_reader.h: bytes in memory, no file on disk guaranteed).
  /// Throws SceneError naming the texture's origin and file when an image cannot be read or
  /// decoded, has no pixels, or holds NaN/Inf/negative values.
  TextureSet(const std::vector<Texture>& textures, const FileReader& reader);

  /// value * texture(uv) (or value for a constant), linear RGB.
  glm::vec3 eval(const TexturedColor& c, glm::vec2 uv) const;
  /// value * the texture's scalar lookup (Mitsuba's eval_1: the single channel, or the
  /// luminance of RGB), or value for a constant.
  float eval(const TexturedFloat& f, glm::vec2 uv) const;
  /// The texture alone (linear RGB). `texture` must be an index into the scene's textures.
  glm::vec3 lookup(int32_t texture, glm::vec2 uv) const;
  /// The scalar lookup alone (see eval(TexturedFloat)).
  float lookup_1(int32_t texture, glm::vec2 uv) const;
  /// The texture at a surface point: a mesh_attribute reads the point's shape attributes (a
  /// 1-channel attribute as grey, a 3-channel one as RGB, 0 without the attribute), a volume
  /// texture the point's world position `at.p`, every other kind looks up `at.uv`. The
  /// uv-only lookups above read a mesh_attribute as 0 and a volume grid as 0 (only materials
  /// may use them, and materials look up surface points; the loaders check that).
  glm::vec3 lookup(int32_t texture, const TexturePoint& at) const;
  /// Scalar lookup at a surface point: a 1-channel mesh attribute's value; a 3-channel one
  /// reads 0, as Mitsuba's eval_1 of it (Mesh::eval_attribute_1 returns 0 for another size);
  /// a volume texture's eval_1 at `at.p`.
  float lookup_1(int32_t texture, const TexturePoint& at) const;
  /// d/du and d/dv of the scalar lookup, for bump mapping (Mitsuba's eval_1_grad). Zero for
  /// raw constants, checkerboards and nearest-filtered bitmaps (piecewise constant; Mitsuba refuses them).
  glm::vec2 gradient(int32_t texture, glm::vec2 uv) const;

  bool empty() const { return textures_.empty(); }
  size_t size() const { return textures_.size(); }

 private:
  /// A mesh_attribute texture: what it reads lives in each shape's MeshAttributeTable.
  struct MeshAttributeRef {
    glm::vec3 eval(glm::vec2 /*uv*/) const { return glm::vec3(0.0f); }
  };
  using Entry =
      std::variant<BitmapTexture, Checkerboard, RawConstant, MeshAttributeRef, VolumeTexture>;
  const Entry& at(int32_t texture) const;

  std::vector<Entry> textures_;
};

}  // namespace tessera
