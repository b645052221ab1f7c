// Scene bundles: validation of paths, the canonical serialization and its hash.
#include "wire/scene_bundle.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "scene/scene_error.h"
#include "wire/sha256.h"

namespace tessera::wire {
namespace {

v1::SceneBundle make(const std::string& scene_file,
                     const std::vector<std::pair<std::string, std::string>>& files) {
  v1::SceneBundle b;
  b.set_scene_file(scene_file);
  for (const auto& [path, data] : files) {
    auto* f = b.add_files();
    f->set_path(path);
    f->set_data(data);
  }
  return b;
}

std::string error_of(const v1::SceneBundle& b) {
  try {
    bundle_from_proto(b);
  } catch (const BundleError& e) {
    return e.what();
  }
  return "";
}

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_TRUE(is_sha256_hex(sha256_hex("x")));
  EXPECT_FALSE(is_sha256_hex("ABC"));
  EXPECT_FALSE(is_sha256_hex(std::string(64, 'g')));
}

TEST(SceneBundle, HashIgnoresFileOrder) {
  const auto a = bundle_from_proto(make("s.json", {{"s.json", "{}"}, {"m/a.ply", "ply"}}));
  const auto b = bundle_from_proto(make("s.json", {{"m/a.ply", "ply"}, {"s.json", "{}"}}));
  EXPECT_EQ(bundle_sha256(a), bundle_sha256(b));
  EXPECT_EQ(canonical_bytes(a), canonical_bytes(b));
}

TEST(SceneBundle, HashChangesWithAnyByte) {
  const auto a = bundle_from_proto(make("s.json", {{"s.json", "{}"}, {"a.ply", "ply"}}));
  const auto b = bundle_from_proto(make("s.json", {{"s.json", "{}"}, {"a.ply", "plz"}}));
  const auto c = bundle_from_proto(make("s.json", {{"s.json", "{}"}, {"b.ply", "ply"}}));
  // Length prefixes keep (path, data) boundaries apart: "a" + "b.ply" != "ab" + ".ply".
  const auto d = bundle_from_proto(make("s.json", {{"s.json", "{}a.ply"}, {"a.ply", ""}}));
  EXPECT_NE(bundle_sha256(a), bundle_sha256(b));
  EXPECT_NE(bundle_sha256(a), bundle_sha256(c));
  EXPECT_NE(bundle_sha256(a), bundle_sha256(d));
}

TEST(SceneBundle, CanonicalBytesRoundTrip) {
  const auto a = bundle_from_proto(
      make("scenes/s.json", {{"scenes/s.json", "{}"}, {"scenes/m/x.obj", std::string("\0\1", 2)}}));
  EXPECT_EQ(parse_canonical(canonical_bytes(a)), a);
  const std::string bytes = canonical_bytes(a);
  EXPECT_THROW(parse_canonical(bytes.substr(0, bytes.size() - 1)), BundleError);
  EXPECT_THROW(parse_canonical(bytes + "x"), BundleError);
  EXPECT_THROW(parse_canonical("not a bundle"), BundleError);
}

TEST(SceneBundle, RefusesBadPaths) {
  EXPECT_NE(error_of(make("s.json", {{"s.json", ""}, {"/etc/passwd", ""}})), "");
  EXPECT_NE(error_of(make("s.json", {{"s.json", ""}, {"../up.ply", ""}})), "");
  EXPECT_NE(error_of(make("s.json", {{"s.json", ""}, {"a/../../b", ""}})), "");
  EXPECT_NE(error_of(make("s.json", {{"s.json", ""}, {"a//b", ""}})), "");
  EXPECT_NE(error_of(make("s.json", {{"s.json", ""}, {"", ""}})), "");
  EXPECT_NE(error_of(make("", {{"s.json", ""}})), "");
  EXPECT_NE(error_of(make("/s.json", {{"s.json", ""}})), "");
}

TEST(SceneBundle, RefusesDuplicatesAndAMissingSceneFile) {
  const std::string dup = error_of(make("s.json", {{"s.json", "1"}, {"s.json", "2"}}));
  EXPECT_NE(dup.find("duplicate"), std::string::npos) << dup;
  const std::string missing = error_of(make("s.json", {{"other.json", "{}"}}));
  EXPECT_NE(missing.find("s.json"), std::string::npos) << missing;
}

TEST(SceneBundle, ReaderTakesBundlePaths) {
  // Paths are relative to the bundle root: a Mitsuba scene below it may name shared folders.
  const auto b = bundle_from_proto(
      make("scenes/s.json", {{"scenes/s.json", "{}"}, {"scenes/meshes/a.ply", "A"}}));
  const FileReader read = bundle_reader(b);
  EXPECT_EQ(read("scenes/meshes/a.ply"), "A");
  EXPECT_THROW(read("meshes/a.ply"), std::exception);
}

TEST(SceneBundle, NativeScenesBelowTheRootNameFilesFromTheirFolder) {
  const std::string scene =
      R"({"tessera": 1, "materials": {"w": {"type": "diffuse"}},
          "shapes": [{"type": "mesh", "file": "meshes/t.obj", "material": "w"}]})";
  const auto b = bundle_from_proto(make(
      "scenes/s.json",
      {{"scenes/s.json", scene}, {"scenes/meshes/t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}}));
  const Scene parsed = parse_bundle_scene(b);
  EXPECT_EQ(parsed.referenced_files, std::vector<std::string>{"scenes/meshes/t.obj"});
}

}  // namespace
}  // namespace tessera::wire

namespace tessera::wire {
namespace {

TEST(SceneBundle, ReaderServesOnlyTheBundlesOwnFiles) {
  BundleContents b;
  b.scene_file = "scenes/scene.json";
  b.files = {{"scenes/scene.json", "{}"}, {"scenes/meshes/m.ply", "mesh"}, {"top.txt", "top"}};
  const FileReader reader = bundle_reader(b);
  EXPECT_EQ(reader("scenes/meshes/m.ply"), "mesh");
  EXPECT_EQ(reader("./scenes/meshes/m.ply"), "mesh");  // "." components are dropped
  EXPECT_EQ(reader("top.txt"), "top");
  // Nothing outside the bundle's root; nothing absolute; never disk.
  for (const char* path : {"../top.txt", "/etc/passwd", "scenes/../../top.txt", "C:\\x", "",
                           "scenes//meshes/m.ply", "meshes/m.ply"}) {
    EXPECT_THROW(reader(path), SceneError) << path;
  }
}

}  // namespace
}  // namespace tessera::wire

namespace tessera::wire {
namespace {

/// A bundle whose bitmap texture is `image` (bytes of a file named `name`).
Scene scene_with_texture(const std::string& name, const std::string& image) {
  const std::string scene =
      R"({"tessera": 1, "textures": {"wood": {"type": "bitmap", "file": ")" + name + R"("}},
          "materials": {"w": {"type": "diffuse", "reflectance": {"texture": "wood"}}},
          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "w"}]})";
  return parse_bundle_scene(bundle_from_proto(make("s.json", {{"s.json", scene}, {name, image}})));
}

TEST(SceneBundle, DefineParametersTravelInTheSceneFile) {
  // `tessera submit -D spp=3`: the server and the workers parse the bundle alone, so the
  // parameter must be in the bundle's scene file (as a <default> on the root tag's line).
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tessera_bundle_define_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "scene.xml")
      << "<scene version=\"3.0.0\">\n  <sensor type=\"perspective\"><sampler type=\"independent\">"
         "<integer name=\"sample_count\" value=\"$spp\"/></sampler></sensor>\n</scene>\n";
  EXPECT_THROW(bundle_from_disk(dir / "scene.xml"), SceneError);  // $spp undefined
  Scene local;
  const BundleContents bundle =
      bundle_from_disk(dir / "scene.xml", &local, std::nullopt, {{"spp", "3"}});
  EXPECT_EQ(local.render.spp, 3);
  EXPECT_EQ(parse_bundle_scene(bundle).render.spp, 3);
  EXPECT_NE(bundle.files.at(bundle.scene_file)
                .find("<scene version=\"3.0.0\"><default name=\"spp\" value=\"3\"/>\n"),
            std::string::npos);
  // Other parameters, another bundle.
  EXPECT_NE(bundle_sha256(bundle),
            bundle_sha256(bundle_from_disk(dir / "scene.xml", nullptr, std::nullopt, {{"spp", "4"}})));
  fs::remove_all(dir);
}

TEST(SceneBundle, ImagesAreDecodedAndCheckedAtSubmitNamingTheTexture) {
  const Scene broken = scene_with_texture("wood.png", "not a PNG at all");
  try {
    check_scene_images(broken);
    FAIL() << "a broken image was accepted";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("textures.wood"), std::string::npos) << message;
    EXPECT_NE(message.find("wood.png"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace tessera::wire
