// A shape's mesh attributes as its `mesh_attribute` textures read them (docs/scenes.md,
// "Mesh attributes").
#pragma once

#include <cstdint>
#include <vector>

#include <glm/gtc/type_precision.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

/// The attributes of one triangle shape that the scene's mesh_attribute textures name, in
/// single precision as Mitsuba stores them. Immutable after construction; lookups are const.
class MeshAttributeTable {
 public:
  MeshAttributeTable() = default;
  /// The columns of `shape` (a triangle shape) named by the mesh_attribute textures among
  /// `textures`; none when it has no attributes or no texture reads them.
  MeshAttributeTable(const Shape& shape, const std::vector<Texture>& textures);

  /// Texture `texture`'s value at barycentrics `b` = (b1, b2) of triangle `primitive`:
  /// a vertex attribute blended as Mitsuba blends it, b0 v0 + b1 v1 + b2 v2 with
  /// b0 = 1 - b1 - b2 (in float, without fused multiply-add), a face attribute its row; times
  /// the texture's scale. `channels` is set to the attribute's (1: the value is in x; 3), or to
  /// 0 when this shape does not have it (the value is then 0).
  glm::vec3 eval(int32_t texture, uint32_t primitive, glm::vec2 b, int& channels) const;

  bool empty() const { return columns_.empty(); }

 private:
  struct Column {
    int32_t texture = -1;
    int channels = 1;
    bool per_vertex = true;
    float scale = 1;
    std::vector<float> values;
  };
  glm::vec3 row(const Column& c, uint32_t index) const;

  std::vector<Column> columns_;
  std::vector<glm::u32vec3> indices_;  ///< the shape's triangles (for vertex attributes)
};

/// Where a texture is looked up: the surface point's (u, v), for mesh attributes the shape's
/// table, the triangle and the hit's barycentrics (b1, b2) (`attributes` null: none), and for
/// volume textures the point's world position `p` (inside an instance too, as Mitsuba's
/// instances hand their textures the world-space interaction).
struct TexturePoint {
  glm::vec2 uv{0.0f};
  const MeshAttributeTable* attributes = nullptr;
  uint32_t primitive = 0;
  glm::vec2 barycentric{0.0f};
  glm::vec3 p{0.0f};
};

}  // namespace tessera
