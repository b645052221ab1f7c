// Bad scenes: every error is one line starting with the JSON path of what is wrong.
#include <gtest/gtest.h>

#include <filesystem>

#include "scene/loader/scene_loader.h"
#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::scene_with_shapes;

TEST(SceneErrors, MalformedJsonGivesLineAndColumn) {
  EXPECT_EQ(error_of("{\"tessera\": 1,\n  \"film\": {\"width\": 12,}\n}"),
            "scene: line 2, column 24: syntax error while parsing object key - unexpected '}'; "
            "expected string literal");
  EXPECT_EQ(error_of("{\"tessera\": 1,\n\n   \"film\": tru }"),
            "scene: line 3, column 15: syntax error while parsing value - invalid literal; last "
            "read: '\"film\": tru '");
  EXPECT_EQ(error_of("{\"tessera\": 1, \"camera\": {\"fov\": NaN}}"),
            "scene: line 1, column 34: syntax error while parsing value - invalid literal; last "
            "read: '\"fov\": N'");
  EXPECT_EQ(error_of(""),
            "scene: line 1, column 1: syntax error while parsing value - unexpected end of input; "
            "expected '[', '{', or a literal");
}

TEST(SceneErrors, DuplicateKey) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov": 30, "fov": 40}})"),
            "camera.fov: duplicate key");
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "sphere"}, {"type": "sphere", "radius": 1, "radius": 2})")),
            "shapes[1].radius: duplicate key");
}

TEST(SceneErrors, UnknownKeys) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "light": []})"),
            "light: unknown key (a scene has: tessera, camera, film, render, textures, materials, "
            "groups, shapes, lights, media)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov_deg": 40}})"),
            "camera.fov_deg: unknown key (the camera has: type, position, look_at, up, fov, "
            "fov_axis, aperture_radius, focus_distance, view_size, view_aspect, medium)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"spp": 4, "threads": 2}})"),
            "render.threads: unknown key (render has: spp, max_depth, rr_depth, seed, "
            "hide_emitters)");
  EXPECT_EQ(
      error_of(scene_with_shapes(R"({"type": "sphere", "material": "white", "colour": [1,0,0]})")),
      "shapes[0].colour: unknown key (a \"sphere\" shape has: type, material, emission, power, "
      "two_sided, flip_normals, transform, interior, exterior, center, radius, frame)");
}

TEST(SceneErrors, WrongTypes) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "film": {"width": "256"}})"),
            "film.width: must be an integer (got a string)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "shapes": {}})"),
            "shapes: must be an array (got an object)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"position": [0, 1]}})"),
            "camera.position: must have 3 elements (got 2)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"up": [0, "1", 0]}})"),
            "camera.up[1]: must be a number (got a string)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"m": {"two_sided": 1}}})"),
            "materials.m.two_sided: must be true or false (got a number)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": null})"), "camera: must be an object (got null)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": 3})")),
            "shapes[0].type: must be a string (got a number)");
}

TEST(SceneErrors, UnknownMaterial) {
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "whte"})")),
            "shapes[0].material: unknown material \"whte\"");
}

TEST(SceneErrors, MissingMeshFile) {
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white"},
      {"type": "sphere", "material": "white"}, {"type": "sphere", "material": "white"},
      {"type": "sphere", "material": "white"},
      {"type": "mesh", "file": "meshes/x.ply", "material": "white"})")),
            "shapes[4].file: meshes/x.ply: no such file in the scene's folder");
  EXPECT_EQ(
      error_of(scene_with_shapes(R"({"type": "mesh", "file": "x.stl", "material": "white"})")),
      "shapes[0].file: x.stl: unsupported mesh format (expected a .obj, .ply or .serialized file)");
}

TEST(SceneErrors, PathsMustStayInsideTheFolder) {
  auto mesh = [](const std::string& file) {
    return error_of(
        scene_with_shapes(R"({"type": "sphere", "material": "white"}, {"type": "mesh", "file": ")" +
                          file + R"(", "material": "white"})"));
  };
  EXPECT_EQ(mesh("../x.obj"),
            "shapes[1].file: path must stay inside the scene's folder (\"../x.obj\")");
  EXPECT_EQ(mesh("meshes/../../x.obj"),
            "shapes[1].file: path must stay inside the scene's folder (\"meshes/../../x.obj\")");
  EXPECT_EQ(mesh("/etc/x.obj"),
            "shapes[1].file: path must be relative to the scene's folder (\"/etc/x.obj\")");
  EXPECT_EQ(mesh("C:\\\\x.obj"),
            "shapes[1].file: path must be relative to the scene's folder (\"C:\\x.obj\")");
  EXPECT_EQ(mesh("meshes//x.obj"),
            "shapes[1].file: path must not have an empty component (\"meshes//x.obj\")");
  EXPECT_EQ(mesh(""), "shapes[1].file: path must not be empty");
}

TEST(SceneErrors, DegenerateExplicitTriangle) {
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white"},
      {"type": "sphere", "material": "white"},
      {"type": "triangles", "material": "white", "vertices": [[0,0,0],[1,0,0],[0,1,0],[2,0,0]],
       "indices": [[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,3]]})")),
            "shapes[2].indices[5]: degenerate triangle (zero area)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "triangles", "material": "white",
       "vertices": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,1]]})")),
            "shapes[0].indices[0]: degenerate triangle (zero area)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "triangles", "material": "white",
       "vertices": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,3]]})")),
            "shapes[0].indices[0][2]: index 3 out of range (3 vertices)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "triangles", "material": "white",
       "vertices": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]], "normals": [[0,0,1],[0,0,0],[0,0,1]]})")),
            "shapes[0].normals[1]: must be a non-zero vector");
}

TEST(SceneErrors, ZeroRadius) {
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "sphere", "material": "white"}, {"type": "sphere", "material": "white"},
      {"type": "sphere", "material": "white"}, {"type": "sphere", "radius": 0, "material": "white"})")),
            "shapes[3].radius: must be > 0 (got 0)");
}

TEST(SceneErrors, NegativeSpp) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"spp": -5}})"),
            "render.spp: must be >= 1 (got -5)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"spp": 0}})"),
            "render.spp: must be >= 1 (got 0)");
}

TEST(SceneErrors, HugeNumbers) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov": 1e999}})"),
            "camera.fov: must be a finite number (1e999 is too large for a double)");
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "sphere", "material": "white", "center": [0, -1e999, 0]})")),
            "shapes[0].center[1]: must be a finite number (-1e999 is too large for a double)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"spp": 1e30}})"),
            "render.spp: is too large for an integer (got 1e+30)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"spp": 99999999999999999999999}})"),
            "render.spp: is too large for an integer (got 1e+23)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"seed": 1e999}})"),
            "render.seed: must be a finite number (1e999 is too large for a double)");
  // Finite inputs whose results overflow are refused too.
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "radius": 1e300, "material": "white",
      "transform": {"scale": 1e10}})")),
            "shapes[0].transform: the sphere does not stay finite");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "radius": 1e-150, "power": 1e10})")),
            "shapes[0]: the radiance of this power overflows (the shape's area is too small)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "radius": 1e-200, "power": 1})")),
            "shapes[0]: a light must have a positive, finite area (got 0)");
}

TEST(SceneErrors, TruncatedPlyAndOutOfRangeIndices) {
  std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string mesh =
      R"({"type": "sphere", "material": "white"}, {"type": "mesh", "file": "meshes/x.ply", "material": "white"})";
  EXPECT_EQ(
      error_of(scene_with_shapes(mesh), {{"meshes/x.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1"}}),
      "shapes[1].file: meshes/x.ply: line 13 (element face, row 0): unexpected end of file");
  EXPECT_EQ(error_of(scene_with_shapes(mesh),
                     {{"meshes/x.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n"}}),
            "shapes[1].file: meshes/x.ply: line 13 (element face, row 0): vertex index -1 out of "
            "range (3 vertices)");
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

// A folder, a missing path and a device are each named for what they are.
TEST(SceneErrors, SceneFileThatIsNotAFile) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path();
  auto message = [](const std::filesystem::path& p) {
    try {
      load_scene_file(p);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(folder),
            folder.string() + ": is a folder, not a scene file (give its .json or .xml scene)");
  EXPECT_EQ(message(folder / "no-such-scene.json"),
            (folder / "no-such-scene.json").string() + ": no such file");
  EXPECT_EQ(message("/dev/null"),
            "/dev/null: not a regular file (a scene must be a .json or .xml file)");
}

}  // namespace
}  // namespace tessera
