// Helpers shared by the tests of Mitsuba sensors (mitsuba_sensor_test.cpp, mitsuba_film_test.cpp,
// and the reference scene's camera in loader/scene_files_test.cpp).
#pragma once

#include <string>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/scene.h"

namespace tessera::testing {

/// A sensor of `type` with `inside` (parameters) and a default film.
inline std::string sensor(const std::string& inside, const std::string& type = "perspective",
                          const std::string& film = "") {
  return "<sensor type=\"" + type + "\">\n" + inside + "\n" +
         (film.empty() ? "<film type=\"hdrfilm\"><rfilter type=\"box\"/></film>" : film) +
         "\n</sensor>\n";
}

inline Scene with_sensor(const std::string& s, const std::string& body = "") {
  return parse_xml(mitsuba_scene(body, s));
}

inline std::string sensor_error(const std::string& s, const std::string& body = "") {
  return xml_error(mitsuba_scene(body, s));
}

/// The camera's image-right direction as Tessera's renderer builds it.
inline glm::dvec3 image_right(const Camera& c) {
  return glm::normalize(glm::cross(glm::normalize(c.look_at - c.position), c.up));
}

}  // namespace tessera::testing
