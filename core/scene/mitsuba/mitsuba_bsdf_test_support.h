// Helpers shared by the tests of Mitsuba BSDFs (mitsuba_bsdf_test.cpp,
// mitsuba_surface_bsdfs_test.cpp): one rectangle holding the BSDF under test.
#pragma once

#include <string>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/scene.h"

namespace tessera::testing {

/// The material of one rectangle holding `bsdf`.
inline Material material_of(const std::string& bsdf) {
  Scene s = parse_xml(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
  return s.materials.at(s.shapes.at(0).material);
}

/// The error of a scene whose rectangle holds `bsdf`.
inline std::string bsdf_error(const std::string& bsdf) {
  return xml_error(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
}

}  // namespace tessera::testing
