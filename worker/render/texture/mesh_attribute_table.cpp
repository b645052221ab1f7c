#include "mesh_attribute_table.h"

namespace tessera {

MeshAttributeTable::MeshAttributeTable(const Shape& shape, const std::vector<Texture>& textures) {
  for (size_t t = 0; t < textures.size(); ++t) {
    if (textures[t].kind != TextureKind::mesh_attribute) continue;
    const MeshAttribute* a = find_mesh_attribute(shape.attributes, textures[t].attribute);
    if (!a) continue;
    Column c;
    c.texture = int32_t(t);
    c.channels = a->channels;
    c.per_vertex = a->per_vertex();
    c.scale = float(textures[t].scale);
    c.values = a->values;
    columns_.push_back(std::move(c));
  }
  if (!columns_.empty()) indices_ = shape.indices;
}

glm::vec3 MeshAttributeTable::row(const Column& c, uint32_t index) const {
  const size_t at = size_t(index) * size_t(c.channels);
  if (c.channels == 1) return glm::vec3(c.values[at]);
  return {c.values[at], c.values[at + 1], c.values[at + 2]};
}

glm::vec3 MeshAttributeTable::eval(int32_t texture, uint32_t primitive, glm::vec2 b,
                                   int& channels) const {
  for (const Column& c : columns_) {
    if (c.texture != texture) continue;
    channels = c.channels;
    if (!c.per_vertex) return row(c, primitive) * c.scale;
    const glm::u32vec3 tri = indices_[primitive];
    const float b0 = 1.0f - b.x - b.y;
    // Mitsuba's blend: a0 b0 + (a1 b1 + a2 b2), here with each product rounded.
    const glm::vec3 v = row(c, tri.x) * b0 + (row(c, tri.y) * b.x + row(c, tri.z) * b.y);
    return v * c.scale;
  }
  channels = 0;
  return glm::vec3(0.0f);
}

}  // namespace tessera
