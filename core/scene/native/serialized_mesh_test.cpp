// The native `mesh` shape over a Mitsuba serialized file: the shape it picks, its uvs, and the
// refusals of a bad shape_index.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "scene/mesh/serialized_test_files.h"
#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::file_bytes;
using testing::quad;
using testing::ShapeSpec;

TEST(SerializedLoader, NativeMeshShapeTakesShapeIndexAndKeepsUvs) {
  std::vector<ShapeSpec> shapes = {quad(0), quad(3)};
  shapes[1].flags |= 0x2;
  shapes[1].uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  std::map<std::string, std::string> files = {{"m.serialized", file_bytes(shapes)}};
  Scene scene = testing::parse(
      testing::scene_with_shapes(
          R"({"type": "mesh", "file": "m.serialized", "shape_index": 1, "material": "white"})"),
      files);
  ASSERT_EQ(scene.shapes.size(), 1u);
  EXPECT_EQ(scene.shapes[0].positions[0].z, 3);
  ASSERT_EQ(scene.shapes[0].uvs.size(), 4u);
  EXPECT_EQ(scene.shapes[0].uvs[2], glm::dvec2(1, 1));
  EXPECT_EQ(scene.referenced_files, std::vector<std::string>{"m.serialized"});
  EXPECT_EQ(testing::error_of(testing::scene_with_shapes(
                                  R"({"type": "mesh", "file": "m.serialized", "shape_index": -1,
                                      "material": "white"})"),
                              files),
            "shapes[0].shape_index: must be in [0, 2147483647] (got -1)");
  EXPECT_EQ(testing::error_of(testing::scene_with_shapes(
                                  R"({"type": "mesh", "file": "m.serialized", "shape_index": 2,
                                      "material": "white"})"),
                              files),
            "shapes[0].file: m.serialized: shape_index 2 out of range (the file holds 2 shapes)");
}

}  // namespace
}  // namespace tessera
