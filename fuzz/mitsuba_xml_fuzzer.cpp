// libFuzzer target: the Mitsuba 3 XML importer (core/scene/mitsuba/) on arbitrary bytes.
//
// Build and run: docs/mitsuba.md, "Fuzzing". The input is the scene file; the bundle around
// it holds a sensor to include (so that seeds from tests/data/mitsuba reach the shapes), the
// input itself as "inc.xml" (so that includes recurse into fuzzed text), and tiny mesh files.
//
// Every input is read twice: as the scene file itself, and as a graph of BSDFs that name each
// other through <ref> (reference_graph_scene: each byte pair picks a wrapper type and the BSDF
// it names), so that cycles and long chains of references, which random bytes rarely spell out
// as XML, are tried on every run.
//
// Besides crashes, leaks and undefined behaviour, it checks the importer's promises:
// - every failure is a SceneError whose message is one line;
// - a scene it accepts converts to native JSON that parse_scene accepts, and converting that
//   again gives the same text (the round trip is exact).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"
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

/// A scene of up to 80 BSDFs b0, b1, ..., read from `data` two bytes a BSDF: the first picks
/// its type (diffuse, twosided, mask, blendbsdf with a diffuse beside, or twosided with two
/// sides), the second the BSDF it names (b0 .. b79, so a byte may name itself, an earlier one
/// or a later one). A rectangle uses b0.
std::string reference_graph_scene(std::string_view data) {
  const size_t count = std::min<size_t>(data.size() / 2, 80);
  std::string xml = "<scene version=\"3.0.0\"><include filename=\"sensor.xml\"/>\n";
  for (size_t i = 0; i < count; ++i) {
    const auto type = uint8_t(data[2 * i]) % 5;
    const std::string ref =
        "<ref id=\"b" + std::to_string(uint8_t(data[2 * i + 1]) % std::max<size_t>(count, 1)) +
        "\"/>";
    const std::string id = "id=\"b" + std::to_string(i) + "\"";
    if (type == 0) xml += "<bsdf type=\"diffuse\" " + id + "/>\n";
    if (type == 1) xml += "<bsdf type=\"twosided\" " + id + ">" + ref + "</bsdf>\n";
    if (type == 2) xml += "<bsdf type=\"mask\" " + id + ">" + ref + "</bsdf>\n";
    if (type == 3) {
      xml += "<bsdf type=\"blendbsdf\" " + id + "><float name=\"weight\" value=\"0.5\"/>" + ref +
             "<bsdf type=\"diffuse\"/></bsdf>\n";
    }
    if (type == 4) {
      xml += "<bsdf type=\"twosided\" " + id + "><bsdf type=\"diffuse\"/>" + ref + "</bsdf>\n";
    }
  }
  return xml + "<shape type=\"rectangle\">" + (count ? "<ref id=\"b0\"/>" : "") +
         "</shape></scene>";
}

/// Reads `text` as scene file "fuzz.xml" with the bundle of `reader` and checks the promises
/// above.
void check_scene(std::string_view text, const tessera::FileReader& reader) {
  tessera::Scene scene;
  try {
    scene = tessera::parse_mitsuba_scene(text, "fuzz.xml", reader);
  } catch (const tessera::SceneError& e) {
    if (std::string_view(e.what()).find('\n') != std::string_view::npos) {
      broken_promise("a SceneError of more than one line:", e.what());
    }
    return;
  }
  std::string json;
  try {
    json = tessera::write_scene_json(scene);
    std::string again = tessera::write_scene_json(tessera::parse_scene(json, reader));
    if (again != json) broken_promise("converting twice changed the JSON:", json);
  } catch (const tessera::SceneError& e) {
    broken_promise("an imported scene did not convert and read back:", e.what());
  }
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
  check_scene(text, reader);
  check_scene(reference_graph_scene(text), reader);
  return 0;
}
