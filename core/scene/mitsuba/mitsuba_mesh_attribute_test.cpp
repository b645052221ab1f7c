// Mitsuba's mesh attributes: read from PLY files under Mitsuba's names, carried by the native
// format (writer round trip), and refused where a material needs one its shape lacks.
#include "scene/mesh_attribute.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

/// A unit square as one quad face (two triangles) and one triangle, in ASCII: vertex colours as
/// uchar r g b, a one-channel vertex attribute temp_0, a two-field pair that Mitsuba drops
/// (pair_x pair_y), and float face colours color_0..2 (Mitsuba's "face_color").
std::string attributed_ply() {
  return "ply\nformat ascii 1.0\nelement vertex 5\n"
         "property float x\nproperty float y\nproperty float z\n"
         "property uchar r\nproperty uchar g\nproperty uchar b\n"
         "property float temp_0\nproperty float pair_x\nproperty float pair_y\n"
         "element face 2\nproperty list uchar int vertex_indices\n"
         "property float color_0\nproperty float color_1\nproperty float color_2\n"
         "end_header\n"
         "0 0 0 255 0 0 0.5 9 9\n"
         "1 0 0 0 255 0 1.5 9 9\n"
         "1 1 0 0 0 255 2.5 9 9\n"
         "0 1 0 128 128 128 3.5 9 9\n"
         "0 0 1 0 0 0 4.5 9 9\n"
         "4 0 1 2 3 0.25 0.5 0.75\n"
         "3 0 4 1 1 0 0.125\n";
}

Shape load(const std::string& extra_shape = "") {
  Scene scene = parse(scene_with_shapes(R"({"type": "mesh", "file": "m.ply", "material": "white")" +
                                        extra_shape + "}"),
                      {{"m.ply", attributed_ply()}});
  return scene.shapes.at(0);
}

double srgb_decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(MeshAttributes, PlyPropertiesUnderMitsubasNames) {
  Shape s = load();
  ASSERT_EQ(s.indices.size(), 3u);  // the quad fanned into two triangles, then the triangle
  ASSERT_EQ(s.attributes.size(), 3u);
  const MeshAttribute* color = find_mesh_attribute(s.attributes, "vertex_color");
  const MeshAttribute* temp = find_mesh_attribute(s.attributes, "vertex_temp");
  const MeshAttribute* face = find_mesh_attribute(s.attributes, "face_color");
  ASSERT_TRUE(color && temp && face);
  EXPECT_EQ(find_mesh_attribute(s.attributes, "vertex_pair"), nullptr);  // 2 fields: dropped
  EXPECT_EQ(color->channels, 3);
  ASSERT_EQ(color->values.size(), 15u);
  // Integer fields are normalised and sRGB-decoded, as Mitsuba's PLY reader converts them.
  EXPECT_EQ(color->values[0], 1.0f);
  EXPECT_EQ(color->values[1], 0.0f);
  EXPECT_EQ(color->values[9], float(srgb_decode(128.0 / 255.0)));
  EXPECT_NEAR(color->values[9], 0.2158605, 1e-6);
  EXPECT_EQ(temp->channels, 1);
  EXPECT_EQ(temp->values, (std::vector<float>{0.5f, 1.5f, 2.5f, 3.5f, 4.5f}));
  // One row per triangle: both triangles of the quad carry its row.
  EXPECT_EQ(face->channels, 3);
  EXPECT_EQ(face->values, (std::vector<float>{0.25f, 0.5f, 0.75f, 0.25f, 0.5f, 0.75f, 1, 0,
                                              0.125f}));
}

TEST(MeshAttributes, RgbWithoutPrefixAndPostfixCategories) {
  auto names = [](const std::string& properties, const std::string& row) {
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\n" + properties +
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0 " + row + "\n1 0 0 " + row + "\n0 1 0 " + row + "\n3 0 1 2\n";
    Scene scene = parse(scene_with_shapes(R"({"type": "mesh", "file": "m.ply", "material": "white"})"),
                        {{"m.ply", ply}});
    std::string out;
    for (const MeshAttribute& a : scene.shapes.at(0).attributes) {
      out += a.name + ":" + std::to_string(a.channels) + " ";
    }
    return out;
  };
  EXPECT_EQ(names("property float red\nproperty float green\nproperty float blue\n", "1 1 1"),
                  "vertex_color:3 ");
  EXPECT_EQ(names("property float c_r\nproperty float c_g\nproperty float c_b\n", "1 1 1"),
                  "vertex_c_color:3 ");
  EXPECT_EQ(names("property float d_x\nproperty float d_y\nproperty float d_z\n", "1 1 1"),
                  "vertex_d:3 ");
  EXPECT_EQ(names("property float w_1\n", "1"), "vertex_w:1 ");
  // A broken sequence, four fields, and a name without a one-letter postfix are left out.
  EXPECT_EQ(names("property float e_x\nproperty float e_z\nproperty float e_y\n", "1 1 1"), "");
  EXPECT_EQ(names("property float q_0\nproperty float q_1\nproperty float q_2\n"
                  "property float q_3\n", "1 1 1 1"), "");
  EXPECT_EQ(names("property float quality\n", "1"), "");
  // Colour with alpha: Mitsuba makes a 4-channel attribute its textures read as 0.
  EXPECT_EQ(names("property uchar r\nproperty uchar g\nproperty uchar b\nproperty uchar a\n",
                  "1 1 1 1"), "");
}

const std::string kAttributeMaterials =
    R"("textures": {"vc": {"type": "mesh_attribute", "attribute": "vertex_color"},
                    "fc": {"type": "mesh_attribute", "attribute": "face_color", "scale": 0.5},
                    "missing": {"type": "mesh_attribute", "attribute": "vertex_missing"}},
       "materials": {"vertex": {"type": "diffuse", "reflectance": {"texture": "vc"}},
                     "face": {"type": "rough_conductor", "alpha": {"texture": "fc"}},
                     "none": {"type": "diffuse", "reflectance": {"texture": "missing"}}},)";

std::string attribute_scene(const std::string& material) {
  return R"({"tessera": 1, )" + kAttributeMaterials +
         R"("shapes": [{"type": "mesh", "file": "m.ply", "material": ")" + material + R"("}]})";
}

TEST(MeshAttributes, NativeTexturesAndWriterRoundTrip) {
  Scene scene = parse(attribute_scene("vertex"), {{"m.ply", attributed_ply()}});
  ASSERT_EQ(scene.textures.size(), 3u);
  EXPECT_EQ(scene.textures[1].kind, TextureKind::mesh_attribute);
  EXPECT_EQ(scene.textures[1].attribute, "face_color");
  EXPECT_EQ(scene.textures[1].scale, 0.5);
  // The writer spells the mesh out as triangles with their attributes; reading it back gives
  // the same scene, bit for bit.
  const std::string once = write_scene_json(scene);
  EXPECT_NE(once.find("\"attributes\": {"), std::string::npos);
  Scene back = parse(once);
  EXPECT_EQ(back.shapes.at(0).attributes, scene.shapes.at(0).attributes);
  EXPECT_EQ(write_scene_json(back), once);
}

TEST(MeshAttributes, Refusals) {
  const std::string error = error_of(attribute_scene("none"), {{"m.ply", attributed_ply()}});
  EXPECT_NE(error.find("shapes[0]: its material \"none\" reads mesh attribute \"vertex_missing\""
                       " (texture \"missing\"), which the shape does not have (it has "
                       "vertex_color, vertex_temp, face_color)"),
            std::string::npos)
      << error;
  // A sphere has no attributes at all.
  const std::string sphere = R"({"tessera": 1, )" + kAttributeMaterials +
                             R"("shapes": [{"type": "sphere", "material": "vertex"}]})";
  EXPECT_NE(error_of(sphere).find("which the shape does not have (it has no attributes)"),
            std::string::npos)
      << error_of(sphere);
  EXPECT_NE(error_of(R"({"tessera": 1, "textures": {"t": {"type": "mesh_attribute",
                          "attribute": "color"}}, "shapes": []})")
                .find("textures.t.attribute: must start with \"vertex_\" or \"face_\""),
            std::string::npos);
  // Inline attributes: one row per vertex or triangle, 1 or 3 channels.
  auto triangles = [](const std::string& attributes) {
    return error_of(scene_with_shapes(R"({"type": "triangles", "material": "white",
        "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]],
        "attributes": )" + attributes + "}"));
  };
  EXPECT_EQ(triangles(R"({"vertex_t": [1, 2, 3], "face_c": [[1, 0, 0]]})"), "(no error)");
  EXPECT_NE(triangles(R"({"vertex_t": [1, 2]})")
                .find("attribute \"vertex_t\": 2 values for 3 vertices of 1 channel"),
            std::string::npos)
      << triangles(R"({"vertex_t": [1, 2]})");
  EXPECT_NE(triangles(R"({"corner_t": [1, 2, 3]})")
                .find("attribute \"corner_t\": the name must start with"),
            std::string::npos);
}

TEST(MeshAttributes, MitsubaTextureAndRefusalNamingTheAttribute) {
  const std::string shape = R"(<shape type="ply"><string name="filename" value="m.ply"/>
      <bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
      <string name="name" value="NAME"/><float name="scale" value="2"/></texture></bsdf></shape>)";
  auto with_name = [&](const std::string& name) {
    std::string s = shape;
    s.replace(s.find("NAME"), 4, name);
    return testing::mitsuba_scene(s);
  };
  Scene scene = testing::parse_xml(with_name("face_color"), {{"m.ply", attributed_ply()}});
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].kind, TextureKind::mesh_attribute);
  EXPECT_EQ(scene.textures[0].scale, 2);
  EXPECT_NE(find_mesh_attribute(scene.shapes.at(0).attributes, "face_color"), nullptr);
  const std::string error =
      testing::xml_error(with_name("vertex_colour"), {{"m.ply", attributed_ply()}});
  EXPECT_NE(error.find("test.xml: line "), std::string::npos) << error;
  EXPECT_NE(error.find("reads mesh attribute \"vertex_colour\""), std::string::npos) << error;
  EXPECT_NE(testing::xml_error(with_name("colour"), {{"m.ply", attributed_ply()}})
                .find("must start with \"vertex_\" or \"face_\" (got \"colour\")"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
