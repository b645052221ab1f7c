// libFuzzer targets: the scene format v1 parser (core/scene) on arbitrary bytes, built three
// times (fuzz/CMakeLists.txt), one per input format, with TESSERA_FUZZ_FORMAT set to
//   1 (scene_json_fuzzer): the input is the scene JSON; the bundle around it holds a small OBJ
//     (with an MTL) and a small PLY that seeds may reference;
//   2 (obj_mesh_fuzzer): the input is "m.obj", referenced by a fixed scene (materials on, so
//     the fuzzed OBJ's mtllib reaches "m.mtl", which is the input too);
//   3 (ply_mesh_fuzzer): the input is "m.ply", referenced by a fixed scene;
//   4 (serialized_mesh_fuzzer): the input is "m.serialized" (Mitsuba's format), referenced by
//     a fixed scene that loads its shape 1 (so the end-of-file dictionary is read too).
// Seeds: fuzz/corpus/{scene_json,obj_mesh,ply_mesh,serialized_mesh}/. Run them with fuzz/run.sh.
//
// Besides crashes, leaks and undefined behaviour (ASan, UBSan), it checks the parser's promise
// to users: every refusal is a SceneError with a one-line message (the CLI prints it as is).
// Anything else escaping — std::bad_alloc from a size taken on trust, std::out_of_range, a
// nlohmann exception — is a finding, and aborts.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"

#ifndef TESSERA_FUZZ_FORMAT
#error "define TESSERA_FUZZ_FORMAT (1 json, 2 obj, 3 ply, 4 serialized)"
#endif

namespace {

constexpr const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nelement face 2\n"
    "property list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 2\n3 0 2 3\n";

constexpr const char* kObj =
    "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
    "usemtl red\nf 1//1 2//1 3//1 4//1\nf 1 3 4\n";

constexpr const char* kMtl = "newmtl red\nKd 0.8 0.1 0.1\nKe 0 0 0\n";

/// A scene that loads `file` as a mesh (with the file's materials for OBJ; shape 1 of a
/// serialized file).
std::string mesh_scene(const std::string& file) {
  const char* index = file.ends_with(".serialized") ? R"(, "shape_index": 1)" : "";
  return std::string(
             R"({"tessera": 1, "camera": {"position": [0,0,3], "look_at": [0,0,0], "fov": 40},
    "film": {"width": 8, "height": 8},
    "materials": {"white": {"type": "diffuse", "reflectance": [0.5,0.5,0.5]}},
    "shapes": [{"type": "mesh", "file": ")") +
         file + R"(", "material": "white")" + index + R"(},
      {"type": "quad", "vertices": [[-1,2,-1],[1,2,-1],[1,2,1],[-1,2,1]], "emission": [5,5,5]}]})";
}

[[noreturn]] void broken_promise(const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  constexpr int format = TESSERA_FUZZ_FORMAT;
  const tessera::FileReader reader = [&input](const std::string& path) -> std::string {
    if (path == "m.ply") return format == 3 ? input : kPly;
    if (path == "m.obj") return format == 2 ? input : kObj;
    if (path == "m.mtl") return format == 2 ? input : kMtl;
    if (path == "m.serialized" && format == 4) return input;
    throw tessera::SceneError(path + ": no such file in the scene's folder");
  };
  const char* const mesh_files[] = {"", "", "m.obj", "m.ply", "m.serialized"};
  const std::string scene_text = format == 1 ? input : mesh_scene(mesh_files[format]);
  try {
    (void)tessera::parse_scene(scene_text, reader);
  } catch (const tessera::SceneError& e) {
    if (std::string_view(e.what()).find('\n') != std::string_view::npos) {
      broken_promise("a SceneError of more than one line:", e.what());
    }
  } catch (const std::exception& e) {
    broken_promise("an exception other than SceneError escaped the parser:", e.what());
  }
  return 0;
}
