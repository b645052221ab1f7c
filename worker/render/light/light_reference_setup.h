// Test support for the textured spot and projector tests: the texture and the frame their
// Mitsuba reference scripts (mitsuba_spot_reference.py, mitsuba_projector_reference.py) use.
#pragma once

#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "render/texture/texture_set.h"
#include "render/texture/texture_test_images.h"

namespace tessera::test {

/// 4 x 3 linear float texels (1 + x + 4 y, 0.5 (x + 1), 0.25 (y + 1)), bilinear, repeat: one
/// texture named `name` read from the EXR `file`.
inline TextureSet reference_light_texture(const std::string& name, const std::string& file) {
  std::vector<float> texels;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      texels.insert(texels.end(), {1.0f + x + 4 * y, 0.5f * (x + 1), 0.25f * (y + 1)});
    }
  }
  Texture t;
  t.name = name;
  t.origin = "textures[0]";
  t.file = file;
  t.color_space = TextureColorSpace::linear;
  return TextureSet({t}, memory_reader({{file, encode_image(file, 4, 3, 3, texels,
                                                            OIIO::TypeDesc::FLOAT)}}));
}

/// The light's to_world in both scripts: at (1, 2, 3), turned 30 degrees about y, then -50
/// about x.
inline glm::dmat4 reference_light_frame() {
  return glm::translate(glm::dmat4(1.0), {1, 2, 3}) *
         glm::rotate(glm::dmat4(1.0), glm::radians(30.0), {0, 1, 0}) *
         glm::rotate(glm::dmat4(1.0), glm::radians(-50.0), {1, 0, 0});
}

}  // namespace tessera::test
