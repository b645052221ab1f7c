// libFuzzer target: the Mitsuba 3 XML importer (core/scene/mitsuba/) on arbitrary bytes.
//
// Build and run: docs/mitsuba.md, "Fuzzing". The input is the scene file; the bundle around
// it holds a sensor to include (so that seeds from tests/data/mitsuba reach the shapes), the
// input itself as "inc.xml" (so that includes recurse into fuzzed text), and tiny mesh files.
//
// Besides crashes, leaks and undefined behaviour, it checks the importer's promises:
// - every failure is a SceneError whose message is one line;
// - a scene it accepts converts to native JSON that parse_scene accepts, and converting that
//   again gives the same text (the round trip is exact).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "scene/native/scene_writer.h"

namespace {

constexpr const char* kSensor = R"(<scene version="3.0.0">
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0, 0.5, 2.8" target="0, 0, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
      <rfilter type="box"/></film></sensor></scene>)";

constexpr const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nelement face 2\n"
    "property list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 2\n3 0 2 3\n";

constexpr const char* kObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
    "f 1//1 2//1 3//1 4//1\nf 1 3 4\n";

[[noreturn]] void broken_promise(const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const tessera::FileReader reader = [text](const std::string& path) -> std::string {
    if (path == "sensor.xml") return kSensor;
    if (path == "inc.xml") return std::string(text);
    if (path == "m.ply") return kPly;
    if (path == "m.obj") return kObj;
    throw tessera::SceneError(path + ": no such file in the scene's folder");
  };
  tessera::Scene scene;
  try {
    scene = tessera::parse_mitsuba_scene(text, "fuzz.xml", reader);
  } catch (const tessera::SceneError& e) {
    if (std::string_view(e.what()).find('\n') != std::string_view::npos) {
      broken_promise("a SceneError of more than one line:", e.what());
    }
    return 0;
  }
  std::string json;
  try {
    json = tessera::write_scene_json(scene);
    std::string again = tessera::write_scene_json(tessera::parse_scene(json, reader));
    if (again != json) broken_promise("converting twice changed the JSON:", json);
  } catch (const tessera::SceneError& e) {
    broken_promise("an imported scene did not convert and read back:", e.what());
  }
  return 0;
}
