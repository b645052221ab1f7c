// mesh_attribute lookups: vertex attributes blended by barycentrics, face attributes per
// triangle, channels as Mitsuba's RGB variants read them.
#include "mesh_attribute_table.h"

#include <gtest/gtest.h>

#include "texture_set.h"

namespace tessera {
namespace {

Texture attribute_texture(const std::string& name, double scale = 1) {
  Texture t;
  t.kind = TextureKind::mesh_attribute;
  t.name = name;
  t.attribute = name;
  t.scale = scale;
  return t;
}

/// Two triangles sharing an edge, with a colour and a scalar per vertex and a colour per face.
Shape two_triangles() {
  Shape s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  s.indices = {{0, 1, 2}, {1, 3, 2}};
  s.attributes = {{"vertex_color", 3, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0.5f, 0.5f}},
                  {"vertex_height", 1, {0, 1, 2, 4}},
                  {"face_color", 3, {0.25f, 0.5f, 0.75f, 1, 1, 0}}};
  return s;
}

TEST(MeshAttributeTable, VertexAttributesBlendByBarycentricsFaceAttributesAreConstant) {
  const std::vector<Texture> textures = {attribute_texture("vertex_color"),
                                         attribute_texture("vertex_height", 2),
                                         attribute_texture("face_color"),
                                         attribute_texture("vertex_other")};
  const Shape shape = two_triangles();
  const MeshAttributeTable table(shape, textures);
  const TextureSet set(textures, {});
  auto at = [&](uint32_t primitive, glm::vec2 b) {
    return TexturePoint{{0.9f, 0.9f}, &table, primitive, b};
  };
  // Triangle 0 at barycentrics (b1, b2) = (0.25, 0.5): b0 = 0.25.
  EXPECT_EQ(set.lookup(0, at(0, {0.25f, 0.5f})), glm::vec3(0.25f, 0.25f, 0.5f));
  // At a vertex the vertex's own row; triangle 1's corners are vertices 1, 3, 2.
  EXPECT_EQ(set.lookup(0, at(1, {1, 0})), glm::vec3(0.5f));
  EXPECT_EQ(set.lookup(0, at(1, {0, 0})), glm::vec3(0, 1, 0));
  // A one-channel attribute is grey in colour lookups and itself in scalar ones, times scale.
  EXPECT_EQ(set.lookup_1(1, at(1, {0.5f, 0.5f})), 2 * (0.5f * 4 + 0.5f * 2));
  EXPECT_EQ(set.lookup(1, at(0, {0.5f, 0})), glm::vec3(1.0f));
  // A face attribute is its triangle's row wherever the triangle is hit.
  EXPECT_EQ(set.lookup(2, at(1, {0.1f, 0.3f})), glm::vec3(1, 1, 0));
  EXPECT_EQ(set.lookup(2, at(0, {0.7f, 0.2f})), glm::vec3(0.25f, 0.5f, 0.75f));
  // Mitsuba's eval_1 of a three-channel attribute is 0.
  EXPECT_EQ(set.lookup_1(0, at(0, {0.25f, 0.5f})), 0.0f);
  // An attribute the shape lacks, or a point without attributes, reads 0.
  EXPECT_EQ(set.lookup(3, at(0, {0.25f, 0.5f})), glm::vec3(0.0f));
  EXPECT_EQ(set.lookup(0, TexturePoint{{0.5f, 0.5f}}), glm::vec3(0.0f));
  EXPECT_EQ(set.lookup(0, glm::vec2(0.5f, 0.5f)), glm::vec3(0.0f));
}

TEST(MeshAttributeTable, KeepsOnlyWhatTexturesRead) {
  const Shape shape = two_triangles();
  EXPECT_TRUE(MeshAttributeTable(shape, {}).empty());
  EXPECT_TRUE(MeshAttributeTable(shape, {attribute_texture("face_missing")}).empty());
  EXPECT_FALSE(MeshAttributeTable(shape, {attribute_texture("face_color")}).empty());
}

}  // namespace
}  // namespace tessera
