// The scene bundle: bundle paths, reading files from the scene's folder, load_scene_file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "scene/loader/scene_loader.h"
#include "scene/scene_test_support.h"

namespace tessera {
namespace {

namespace fs = std::filesystem;

std::string bundle_error(const std::string& path) {
  try {
    check_bundle_path(path, "ctx");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneBundlePath, NormalisesRelativePaths) {
  EXPECT_EQ(check_bundle_path("meshes/bunny.ply", "ctx"), "meshes/bunny.ply");
  EXPECT_EQ(check_bundle_path("./meshes/./bunny.ply", "ctx"), "meshes/bunny.ply");
  EXPECT_EQ(check_bundle_path("meshes\\bunny.ply", "ctx"), "meshes/bunny.ply");
  EXPECT_EQ(check_bundle_path("a..b/c...obj", "ctx"), "a..b/c...obj");  // ".." only as a component
}

TEST(SceneBundlePath, RefusesPathsLeavingTheBundle) {
  EXPECT_EQ(bundle_error("../x.obj"),
            "ctx: path must stay inside the scene's folder (\"../x.obj\")");
  EXPECT_EQ(bundle_error("a/..\\..\\x.obj"),
            "ctx: path must stay inside the scene's folder (\"a/..\\..\\x.obj\")");
  EXPECT_EQ(bundle_error("/x.obj"),
            "ctx: path must be relative to the scene's folder (\"/x.obj\")");
  EXPECT_EQ(bundle_error("\\\\server\\x.obj"),
            "ctx: path must be relative to the scene's folder (\"\\\\server\\x.obj\")");
  EXPECT_EQ(bundle_error("d:x.obj"),
            "ctx: path must be relative to the scene's folder (\"d:x.obj\")");
  EXPECT_EQ(bundle_error("a//x.obj"), "ctx: path must not have an empty component (\"a//x.obj\")");
  EXPECT_EQ(bundle_error("meshes/"), "ctx: path must not have an empty component (\"meshes/\")");
  EXPECT_EQ(bundle_error("."), "ctx: path must name a file (\".\")");
  EXPECT_EQ(bundle_error(""), "ctx: path must not be empty");
  EXPECT_EQ(bundle_error(std::string("a\0b", 3)),
            "ctx: path must not contain a NUL character (\"a\\x00b\")");
  // A newline in a file name (found by the scene fuzzer) would split the error over two lines.
  EXPECT_EQ(bundle_error("r\nder/x.obj"),
            "ctx: path must not contain a control character (\"r\\x0ader/x.obj\")");
  EXPECT_EQ(bundle_error("a\x7f.obj"), "ctx: path must not contain a control character (\"a\\x7f.obj\")");
}

/// A fresh folder under the system's temporary directory, removed afterwards.
class SceneBundle : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("tessera-scene-test-" + std::to_string(::getpid()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "scene" / "meshes");
    write("scene/meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write("outside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  }
  void TearDown() override { fs::remove_all(root_); }

  void write(const std::string& relative, const std::string& text) {
    std::ofstream(root_ / relative, std::ios::binary) << text;
  }
  fs::path folder() const { return root_ / "scene"; }

  static std::string read_error(const FileReader& reader, const std::string& path) {
    try {
      reader(path);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "(no error)";
  }

  fs::path root_;
};

TEST_F(SceneBundle, FolderReaderReadsFilesInside) {
  FileReader reader = folder_reader(folder());
  EXPECT_EQ(reader("meshes/tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write("scene/empty.ply", "");
  EXPECT_EQ(reader("empty.ply"), "");
  EXPECT_EQ(read_error(reader, "meshes/none.obj"),
            "meshes/none.obj: no such file in the scene's folder");
  EXPECT_EQ(read_error(reader, "meshes"), "meshes: not a regular file");
  EXPECT_EQ(read_error(reader, "../outside.obj"),
            "../outside.obj: path must stay inside the scene's folder (\"../outside.obj\")");
}

TEST_F(SceneBundle, FolderReaderRefusesSymlinks) {
  fs::create_symlink(root_ / "outside.obj", folder() / "meshes" / "escape.obj");
  fs::create_symlink("tri.obj", folder() / "meshes" / "alias.obj");
  fs::create_directory_symlink(root_, folder() / "up");
  FileReader reader = folder_reader(folder());
  EXPECT_EQ(read_error(reader, "meshes/escape.obj"),
            "meshes/escape.obj: symbolic links are not allowed in a scene's folder");
  EXPECT_EQ(read_error(reader, "meshes/alias.obj"),
            "meshes/alias.obj: symbolic links are not allowed in a scene's folder");
  EXPECT_EQ(read_error(reader, "up/outside.obj"),
            "up/outside.obj: symbolic links are not allowed in a scene's folder");
}

TEST_F(SceneBundle, LoadSceneFileReadsMeshesBesideIt) {
  write("scene/cornell.json", R"({"tessera": 1, "materials": {"white": {}},
      "shapes": [{"type": "mesh", "file": "meshes/tri.obj", "material": "white"}]})");
  Scene scene = load_scene_file(folder() / "cornell.json");
  ASSERT_EQ(scene.shapes.size(), 1u);
  EXPECT_EQ(scene.referenced_files, (std::vector<std::string>{"meshes/tri.obj"}));
}

TEST_F(SceneBundle, LoadSceneFileErrors) {
  write("scene/broken.json", "{\"tessera\": 1,\n  \"film\": {\"width\": 12,}\n}");
  try {
    load_scene_file(folder() / "broken.json");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "broken.json: line 2, column 24: syntax error while parsing object key - "
                 "unexpected '}'; expected string literal");
  }
  write("scene/missing.json", R"({"tessera": 1, "materials": {"white": {}},
      "shapes": [{"type": "mesh", "file": "meshes/x.ply", "material": "white"}]})");
  try {
    load_scene_file(folder() / "missing.json");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "shapes[0].file: meshes/x.ply: no such file in the scene's folder");
  }
  EXPECT_THROW(load_scene_file(folder() / "absent.json"), SceneError);
}

TEST(SceneBundlePath, JoinAllowsDotDotInsideTheRoot) {
  EXPECT_EQ(join_bundle_path("scenes/a/", "../common/x.obj", "ctx"), "scenes/common/x.obj");
  EXPECT_EQ(join_bundle_path("", "meshes\\x.obj", "ctx"), "meshes/x.obj");
  EXPECT_EQ(join_bundle_path("a/", "./b/../c.png", "ctx"), "a/c.png");
  try {
    join_bundle_path("a/", "../../x.obj", "scene.xml: line 3: <string name=\"filename\">", "/data");
    FAIL() << "no error";
  } catch (const BundleEscapeError& e) {
    EXPECT_EQ(e.levels(), 1);
    EXPECT_STREQ(e.what(),
                 "scene.xml: line 3: <string name=\"filename\">: \"../../x.obj\" leaves the bundle "
                 "root (/data): every file a scene names must be inside it (render, convert and "
                 "submit take --root DIR to widen it)");
  }
  EXPECT_THROW(join_bundle_path("a/", "/etc/x", "ctx"), SceneError);
  EXPECT_THROW(join_bundle_path("a/", "x//y", "ctx"), SceneError);
  EXPECT_THROW(join_bundle_path("a/", "..", "ctx"), SceneError);
}

TEST_F(SceneBundle, MitsubaScenesWidenTheDefaultRootToWhatTheyName) {
  // The layout of public scenes: a shared folder beside the scene's folder.
  fs::create_directories(root_ / "common");
  write("common/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write("scene/s.xml", R"(<scene version="3.0.0">
    <path value="../common"/>
    <sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><translate z="-5"/></transform></sensor>
    <shape type="obj"><string name="filename" value="tri.obj"/></shape>
  </scene>)");
  SceneOnDisk loaded = load_scene_bundle(folder() / "s.xml");
  EXPECT_EQ(loaded.root, fs::weakly_canonical(root_));
  EXPECT_EQ(loaded.scene_path, "scene/s.xml");
  EXPECT_EQ(loaded.scene.referenced_files, std::vector<std::string>{"common/tri.obj"});
  // A scene that stays in its folder keeps its folder as the root.
  write("scene/own.xml", R"(<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><translate z="-5"/></transform></sensor>
    <shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape></scene>)");
  SceneOnDisk own = load_scene_bundle(folder() / "own.xml");
  EXPECT_EQ(own.root, fs::weakly_canonical(folder()));
  EXPECT_EQ(own.scene_path, "own.xml");
}

// Without --root, only a <path> may climb out of the scene's folder: an <include> or a file
// name may reach the scene's folder and its <path> folders, not what lies beside them, and is
// refused before anything outside is read (an <include> of ../../etc/passwd read and parsed
// the file).
TEST_F(SceneBundle, ADefaultRootKeepsIncludesAndFileNamesInTheScenesFolders) {
  auto load_error = [&](const std::string& scene) {
    try {
      load_scene_bundle(folder() / scene);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string sensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><translate z="-5"/></transform></sensor>)";
  // Malformed XML outside: were it read, the error would be about its XML.
  write("secret.xml", "<not xml");
  write("scene/include.xml", "<scene version=\"3.0.0\">\n<include filename=\"../secret.xml\"/>\n" +
                                 sensor + "</scene>");
  EXPECT_NE(load_error("include.xml")
                .find("include.xml: line 2: <include>: \"../secret.xml\" leaves the scene's "
                      "folder and its <path> folders (a bundle root given with --root allows it)"),
            std::string::npos)
      << load_error("include.xml");
  write("scene/mesh.xml", "<scene version=\"3.0.0\">\n" + sensor +
                              "\n<shape type=\"obj\"><string name=\"filename\" "
                              "value=\"../outside.obj\"/></shape></scene>");
  EXPECT_NE(load_error("mesh.xml")
                .find("mesh.xml: line 4: <string name=\"filename\">: \"../outside.obj\" leaves "
                      "the scene's folder and its <path> folders"),
            std::string::npos)
      << load_error("mesh.xml");
  // A <path> folder may be reached, and so may what lies below it, also through "..".
  fs::create_directories(root_ / "common" / "meshes");
  write("common/meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write("scene/path.xml", "<scene version=\"3.0.0\">\n<path value=\"../common/meshes\"/>\n" +
                              sensor +
                              "<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/>"
                              "</shape><shape type=\"obj\"><string name=\"filename\" "
                              "value=\"meshes/../meshes/tri.obj\"/></shape></scene>");
  EXPECT_EQ(load_error("path.xml"), "(no error)");
  write("scene/beside.xml", "<scene version=\"3.0.0\">\n<path value=\"../common/meshes\"/>\n" +
                                sensor +
                                "<shape type=\"obj\"><string name=\"filename\" "
                                "value=\"../outside.obj\"/></shape></scene>");
  EXPECT_NE(load_error("beside.xml").find("\"../outside.obj\" is in none of the folders searched"),
            std::string::npos)
      << load_error("beside.xml");
  // With the root given, the same names are read.
  EXPECT_EQ(load_scene_bundle(folder() / "mesh.xml", root_).scene.referenced_files,
            std::vector<std::string>{"outside.obj"});
}

TEST_F(SceneBundle, AGivenRootIsFixed) {
  write("scene/s.xml", R"(<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><translate z="-5"/></transform></sensor>
    <shape type="obj"><string name="filename" value="../outside.obj"/></shape></scene>)");
  SceneOnDisk loaded = load_scene_bundle(folder() / "s.xml", root_);
  EXPECT_EQ(loaded.scene_path, "scene/s.xml");
  EXPECT_EQ(loaded.scene.referenced_files, std::vector<std::string>{"outside.obj"});
  try {
    load_scene_bundle(folder() / "s.xml", folder());
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("s.xml: line 4: <string name=\"filename\">: "
                                         "\"../outside.obj\" leaves the bundle root (" +
                                         fs::weakly_canonical(folder()).string() + ")"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_scene_bundle(folder() / "s.xml", folder() / "meshes"), SceneError);
  EXPECT_THROW(load_scene_bundle(folder() / "s.xml", root_ / "absent"), SceneError);
}

}  // namespace
}  // namespace tessera
