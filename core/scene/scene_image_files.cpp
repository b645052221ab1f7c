#include <algorithm>

#include "scene/image_check.h"

namespace tessera {

std::vector<std::string> scene_image_files(const Scene& scene) {
  std::vector<std::string> files;
  auto add = [&files](const std::string& file) {
    if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
  };
  for (const Texture& texture : scene.textures) {
    if (texture.kind == TextureKind::bitmap) add(texture.file);
  }
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::envmap) add(light.file);
  }
  return files;
}

}  // namespace tessera
