// Helpers shared by the tests that import Mitsuba scenes (core/scene/mitsuba/*_test.cpp, and
// loader/ tests reading them from disk).
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/scene_test_support.h"

namespace tessera::testing {

/// A perspective sensor that Tessera accepts: 64 x 48, box filter, 16 spp, looking from
/// (0, 0, 5) at the origin.
inline std::string mitsuba_sensor() {
  return R"(<sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
    <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/>
      <rfilter type="box"/></film>
  </sensor>
)";
}

/// A Mitsuba 3 scene: `body` after mitsuba_sensor() (or after `sensor` when given).
inline std::string mitsuba_scene(const std::string& body, const std::string& sensor = "") {
  return "<scene version=\"3.0.0\">\n" + (sensor.empty() ? mitsuba_sensor() : sensor) + body +
         "\n</scene>\n";
}

/// A scene using $depth, with `defaults` right after its root tag and `tail` at its end.
inline std::string sampler_scene(const std::string& defaults, const std::string& tail = "") {
  return "<?xml version=\"1.0\"?>\n<scene\n       version=\"3.0.0\">" + defaults +
         "\n" + mitsuba_sensor() +
         "<integrator type=\"path\"><integer name=\"max_depth\" value=\"$depth\"/></integrator>\n"
         + tail + "\n</scene>\n";
}

inline Scene parse_xml(const std::string& xml, std::map<std::string, std::string> files = {}) {
  return parse_mitsuba_scene(xml, "test.xml", memory_reader(std::move(files)));
}

/// The message parse_xml throws, or "(no error)".
inline std::string xml_error(const std::string& xml,
                             std::map<std::string, std::string> files = {}) {
  try {
    parse_xml(xml, std::move(files));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

/// The line of `xml` (1-based) holding the first occurrence of `text`.
inline int line_of(const std::string& xml, const std::string& text) {
  size_t at = xml.find(text);
  EXPECT_NE(at, std::string::npos) << text;
  int line = 1;
  for (size_t i = 0; i < at && i < xml.size(); ++i) line += xml[i] == '\n';
  return line;
}

inline const std::string kSourceDir = TESSERA_SOURCE_DIR;

}  // namespace tessera::testing
