#include "worker_identity.h"

#include <unistd.h>

#include <array>
#include <exception>

#include "render/renderer.h"

namespace tessera::farm {

std::string default_name() {
  std::array<char, 256> host{};
  if (gethostname(host.data(), host.size() - 1) != 0) host[0] = 0;
  return std::string(host.data()) + ":" + std::to_string(getpid());
}

std::string probe_isa() {
  try {
    Scene scene;
    scene.materials.push_back(Material{});
    Shape sphere;
    sphere.kind = Shape::Kind::sphere;
    scene.shapes.push_back(sphere);
    JobOptions options;
    options.width = options.height = 1;
    options.spp = options.batch_spp = 1;
    options.tile_size = 1;
    return Renderer(scene, options).isa();
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace tessera::farm
